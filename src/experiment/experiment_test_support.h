#pragma once
// A scratch folder with the files an experiment file may name, for the experiment tests.

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "experiment/spec.h"

namespace wheelpose::experiment::testing {

inline std::filesystem::path scratch_dir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("wheelpose_experiment_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir / "photos");
  std::ofstream(dir / "real.json") << "{}";
  std::ofstream(dir / "scene.yaml") << "image: {width: 64}\n";
  std::ofstream(dir / "model.json") << "{}";
  return dir;
}

// The train options the tests accept (the real list comes from the train command).
inline CommandOptions test_commands() {
  CommandOptions c;
  c.train = {"steps", "batch", "lr", "seed", "distill", "model", "input-size", "val-every"};
  return c;
}

// A small experiment: a generated and a real set, one training, three models, two variants.
inline const char* kSmallExperiment = R"(name: small
datasets:
  renders:
    generate: {config: scene.yaml, frames: 8, seed: 5}
  real: {coco: real.json, images: photos}
  real-train: {split: {of: real, ratios: [3, 1], part: 0}}
  real-val: {split: {of: real, ratios: [3, 1], part: 1}}
training:
  sets: [renders, {set: real-train, weight: 3}]
  val: real-val
  options: {steps: 20, batch: 4}
models:
  start: model.json
  tuned: trained
  half: {members: trained, blend: 0.5}
scores:
  - {set: real, type: bbox, size: 256}
  - {set: renders, models: [tuned]}
variants:
  real-only: {training.sets: [real-train]}
  distilled: {training.options.distill: 0.1}
)";

}  // namespace wheelpose::experiment::testing
