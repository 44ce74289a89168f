#include "review/clips.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "core/atomic_file.h"
#include "core/error.h"
#include "motion/clip_json.h"

namespace wheelpose::review {

ClipCatalog::ClipCatalog(const std::vector<std::filesystem::path>& folders) {
  if (folders.empty()) throw Error("--clips: give at least one folder of seated-clip JSON files");
  for (const auto& folder : folders) {
    if (!std::filesystem::is_directory(folder)) {
      throw Error(folder.string() + ": not a folder of seated-clip JSON files");
    }
    ClipGroup group;
    group.name = std::filesystem::absolute(folder).lexically_normal().filename().string();
    if (group.name.empty()) {
      group.name = std::filesystem::absolute(folder).lexically_normal().parent_path().filename();
    }
    for (const auto& g : groups_) {
      if (g.name == group.name) {
        throw Error(folder.string() + ": a second clip folder named '" + group.name +
                    "'; group names come from folder names and must differ");
      }
    }
    std::vector<std::filesystem::path> files;
    for (const auto& entry : std::filesystem::directory_iterator(folder)) {
      if (entry.is_regular_file() && entry.path().extension() == ".json") {
        files.push_back(entry.path());
      }
    }
    std::sort(files.begin(), files.end());
    for (const auto& file : files) {
      // Folders written by `motion library` also hold a manifest; only seated clips are shown.
      const auto probe = nlohmann::json::parse(read_file(file), nullptr, false);
      if (probe.is_object() && probe.value("format", "") != "wheelpose.seated_clip") {
        spdlog::info("{}: not a seated clip (format '{}'), skipped", file.string(),
                     probe.value("format", ""));
        continue;
      }
      const motion::SeatedClip clip = motion::read_seated_clip_json(file);
      const std::string id = group.name + "/" + file.stem().string();
      nlohmann::json payload;
      payload["id"] = id;
      payload["fps"] = clip.motion.fps;
      nlohmann::json joints = nlohmann::json::array();
      nlohmann::json parents = nlohmann::json::array();
      for (int j = 0; j < motion::kJointCount; ++j) {
        joints.push_back(std::string(motion::joint_name(j)));
        parents.push_back(motion::joint_parent(j));
      }
      payload["joints"] = std::move(joints);
      payload["parents"] = std::move(parents);
      nlohmann::json frames = nlohmann::json::array();
      for (const auto& pose : clip.positions) {
        nlohmann::json flat = nlohmann::json::array();
        for (const auto& p : pose) {
          for (int k = 0; k < 3; ++k) flat.push_back(std::round(p[k] * 1000.0) / 1000.0);
        }
        frames.push_back(std::move(flat));
      }
      if (frames.empty()) throw Error(file.string() + ": positions: the clip has no frames");
      payload["frames"] = std::move(frames);
      payloads_[id] = payload.dump();
      records_.push_back({id, group.name, static_cast<int>(group.clip_ids.size()),
                          std::filesystem::absolute(file).lexically_normal().string()});
      group.clip_ids.push_back(id);
    }
    if (group.clip_ids.empty()) throw Error(folder.string() + ": no *.json seated clips in it");
    groups_.push_back(std::move(group));
  }
}

}  // namespace wheelpose::review
