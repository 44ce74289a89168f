// Loading the motion clips of a generation run.

#include "generate/motion_source.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "core/atomic_file.h"
#include "core/error.h"
#include "motion/clip_json.h"
#include "motion/library.h"
#include "motion/pipeline.h"

namespace wheelpose::generate {
namespace {

std::vector<motion::SeatedClip> library_seated_clips() {
  const auto motions = motion::library_motions();
  std::vector<motion::SeatedClip> clips(motions.size());
  const motion::MotionOptions options;  // the paper's pipeline, seed 0 as `motion library`
  tbb::parallel_for(std::size_t{0}, motions.size(), [&](std::size_t i) {
    clips[i] =
        motion::run_motion_pipeline(motion::library_clip(motions[i].id, options.seed), options);
  });
  return clips;
}

std::vector<motion::SeatedClip> folder_clips(const std::filesystem::path& folder) {
  if (!std::filesystem::is_directory(folder))
    throw Error(folder.string() + ": not a folder of seated clips (--motions)");
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    const auto& p = entry.path();
    // `wheelpose motion` also writes library.json / summary files beside the clips.
    if (entry.is_regular_file() && p.extension() == ".json" && p.filename() != "library.json" &&
        p.filename() != "summary.json") {
      files.push_back(p);
    }
  }
  std::sort(files.begin(), files.end());
  std::vector<motion::SeatedClip> clips;
  for (const auto& f : files) clips.push_back(motion::read_seated_clip_json(f));
  if (clips.empty()) throw Error(folder.string() + ": no seated clip JSON files (--motions)");
  return clips;
}

// Clip names the ranking keeps: the stem of each kept entry's path, else its id's last part.
std::vector<std::string> kept_names(const std::filesystem::path& ranking) {
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(read_file(ranking));
  } catch (const nlohmann::json::parse_error& e) {
    throw Error(ranking.string() + ": malformed JSON: " + e.what());
  }
  if (!doc.is_object() || !doc.contains("kept") || !doc["kept"].is_array())
    throw Error(ranking.string() +
                ": kept: expected the array written by `wheelpose review filter`");
  std::vector<std::string> names;
  for (std::size_t i = 0; i < doc["kept"].size(); ++i) {
    const auto& k = doc["kept"][i];
    const std::string where = ranking.string() + ": kept[" + std::to_string(i) + "]";
    if (k.contains("path") && k["path"].is_string()) {
      names.push_back(std::filesystem::path(k["path"].get<std::string>()).stem().string());
    } else if (k.contains("id") && k["id"].is_string()) {
      const std::string id = k["id"].get<std::string>();
      names.push_back(id.substr(id.find_last_of('/') + 1));
    } else {
      throw Error(where + ": expected \"id\" or \"path\" strings");
    }
  }
  return names;
}

}  // namespace

std::vector<motion::SeatedClip> load_motion_clips(const MotionSource& source) {
  std::vector<motion::SeatedClip> clips =
      source.folder.empty() ? library_seated_clips() : folder_clips(source.folder);
  if (source.clips_from.empty()) return clips;
  const std::vector<std::string> names = kept_names(source.clips_from);
  std::map<std::string, std::size_t> by_name;
  for (std::size_t i = 0; i < clips.size(); ++i) by_name.emplace(clips[i].motion.name, i);
  std::set<std::size_t> keep;
  for (const std::string& name : names) {
    const auto it = by_name.find(name);
    if (it == by_name.end()) {
      throw Error(
          source.clips_from.string() + ": kept clip '" + name + "' is not among the " +
          std::to_string(clips.size()) + " clips of " +
          (source.folder.empty() ? std::string("the built-in library") : source.folder.string()));
    }
    keep.insert(it->second);
  }
  if (keep.empty()) throw Error(source.clips_from.string() + ": the ranking keeps no clip");
  std::vector<motion::SeatedClip> out;
  for (std::size_t i : keep) out.push_back(std::move(clips[i]));
  return out;
}

}  // namespace wheelpose::generate
