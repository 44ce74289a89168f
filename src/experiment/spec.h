#pragma once
// An experiment as a file: which datasets to make, how to train, which models to score on which
// sets, and named variants (the ablation rows) that override any key of the file. Parsing checks
// everything a run needs before any work starts: unknown keys, missing files, unknown sets and
// models, train options `wheelpose train` does not have. Errors name file:line and the key.

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace wheelpose::experiment {

// A dataset the experiment makes or reads. Paths are absolute (resolved against the folder of
// the experiment file).
struct DatasetSpec {
  enum class Kind { kGenerate, kCoco, kSplit };
  std::string name;
  Kind kind = Kind::kCoco;
  // kGenerate: `wheelpose generate` with these settings.
  std::optional<std::filesystem::path> generate_config, clips_from;
  std::int64_t frames = 0;
  std::uint64_t seed = 0;
  // kCoco: an existing COCO keypoint file and the folder of its images.
  std::filesystem::path coco, images;
  // kSplit: part `part` of `coco split` of dataset `split_of` by image.
  std::string split_of;
  std::vector<double> ratios;
  int part = 0;
};

struct TrainSetRef {
  std::string set;
  double weight = 1;
};

struct TrainingSpec {
  std::vector<TrainSetRef> sets;
  std::string val;  // a dataset name, or empty
  // Which weights `trained` means: "best" (best.pt: the best validation; needs val) or "last".
  std::string keep = "best";
  // Every other `wheelpose train` option, as --name value (flags: value "true").
  std::vector<std::pair<std::string, std::string>> options;
};

// A model to score: one network, or an ensemble of several (predict --model A --model B), each
// a named model (`movenet-multipose`, a shipped model, a .json/.pt path) or `trained` (the
// variant's fine-tuned best.pt), optionally blended with its start (model blend --alpha).
struct ModelSpec {
  std::string name;
  std::vector<std::string> members;
  std::optional<double> blend;  // alpha for `trained` members
  bool flip = false;
  // `trained` members scored as `model export` writes them (a TF.js model with float16
  // weights): the form a model ships in, so a candidate compares like with a shipped model.
  bool exported = false;
};

struct ScoreSpec {
  std::string set;
  std::string type = "both";        // keypoints, bbox or both (eval --type)
  int size = 0;                     // predict --size; 0 = predict's default
  std::vector<std::string> models;  // names in ModelSpec; empty = every model
};

// `intervals:`: how sure each gain is. Every scored model's AP is compared with model `against`
// on the same set by a paired bootstrap over the set's images (eval --bootstrap), in the reports.
struct IntervalSpec {
  std::string against;
  int resamples = 1000;
  std::uint64_t seed = 0;
};

struct ExperimentSpec {
  std::string name, description;
  std::vector<DatasetSpec> datasets;  // in file order
  std::optional<TrainingSpec> training;
  std::vector<ModelSpec> models;
  std::vector<ScoreSpec> scores;
  std::optional<IntervalSpec> intervals;

  const DatasetSpec& dataset(const std::string& name) const;
  bool uses_training() const;
};

struct Variant {
  std::string name;  // "base" for the file as written
  ExperimentSpec spec;
};

// What the caller's commands accept, so option names are checked before any work.
struct CommandOptions {
  std::set<std::string> train;  // long names of `wheelpose train` options
  // Options the experiment sets itself, refused in the file.
  std::set<std::string> reserved = {"train", "out", "val", "resume", "help", "help-all"};
};

// Parses the file; one Variant per `variants:` entry after the base (the base comes first unless
// `run_base: false`). Throws Error naming file:line and key.
std::vector<Variant> load_experiment(const std::filesystem::path& file,
                                     const CommandOptions& commands);

// The same, from text (tests); relative paths resolve against `base_dir`.
std::vector<Variant> parse_experiment(const std::string& text, const std::string& origin,
                                      const std::filesystem::path& base_dir,
                                      const CommandOptions& commands);

}  // namespace wheelpose::experiment
