#pragma once
// An experiment's work as steps: each a few `wheelpose` command lines, in order, writing into
// its own folder under the run's steps/. A step's folder is named by a hash of its commands, so
// variants that share a dataset or a baseline share the step, a resumed run finds its finished
// steps, and a changed setting makes a new step instead of reusing a stale one. The hash also
// reads the files the commands name from outside the run (scenario, clips, annotations,
// weights), so an edited input file is a changed setting too.

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "experiment/spec.h"

namespace wheelpose::experiment {

struct Step {
  std::string id;     // kind-name-hash, also its folder name under steps/
  std::string kind;   // generate, split, train, blend, score
  std::string label;  // for progress lines
  std::vector<std::vector<std::string>> commands;  // wheelpose arguments, without the program
  std::filesystem::path dir;
  // Folders the step may resume from when interrupted (train: checkpoint; generate: frames).
  bool resumable = false;
  // split: its parts' images are the parent's; linked as images/ beside them for `train`.
  std::filesystem::path link_images;
};

// One scored result: which variant, model and set, and where eval wrote metrics.json.
struct ScoreRef {
  std::string variant, model, set, type;
  int size = 0;
  std::filesystem::path metrics;  // metrics.json
  // With `intervals:` (not for the `against` model itself): the set's ground truth, this
  // model's and the baseline model's results.json, and the bootstrap's settings.
  std::filesystem::path gt{}, results{}, baseline_results{};
  std::string baseline_model{};
  int resamples = 0;
  std::uint64_t resample_seed = 0;
};

struct Plan {
  std::vector<Step> steps;  // unique, in run order
  std::vector<ScoreRef> scores;
  std::map<std::string, std::filesystem::path> train_runs;  // variant → its train folder
};

// The files a dataset contributes once its steps have run.
struct DatasetFiles {
  std::filesystem::path coco, images;
};

Plan make_plan(const std::vector<Variant>& variants, const std::filesystem::path& out_dir);

// 64-bit FNV-1a of the text as hex: stable across runs and machines.
std::string stable_hash(const std::string& text);

}  // namespace wheelpose::experiment
