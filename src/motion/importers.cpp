#include "motion/importers.h"

#include <algorithm>
#include <cctype>

#include "core/error.h"
#include "motion/import_bvh.h"
#include "motion/import_keypoints.h"
#include "motion/import_npy.h"

namespace wheelpose::motion {

namespace {

struct ImporterEntry {
  std::string_view format;
  std::vector<std::string_view> extensions;  // lower case, with the dot
  PositionClip (*read)(const std::filesystem::path&, const ImportOptions&);
};

const std::vector<ImporterEntry>& importer_table() {
  static const std::vector<ImporterEntry> table = {
      {"npy", {".npy"}, &import_npy},
      {"bvh", {".bvh"}, &import_bvh},
      {"csv", {".csv"}, &import_keypoints_csv},
      {"json", {".json"}, &import_keypoints_json},
  };
  return table;
}

std::string format_list() {
  std::string list;
  for (const auto& entry : importer_table()) {
    list += (list.empty() ? "" : ", ") + std::string(entry.format);
  }
  return list;
}

}  // namespace

std::vector<std::string> importer_formats() {
  std::vector<std::string> formats;
  for (const auto& entry : importer_table()) formats.emplace_back(entry.format);
  return formats;
}

PositionClip import_motion(const std::filesystem::path& path, const ImportOptions& options) {
  const std::string where = path.string();
  if (options.fps < 0) throw Error(where + ": fps must not be negative");
  if (options.unit_scale < 0) throw Error(where + ": unit scale must not be negative");
  const auto& table = importer_table();
  const ImporterEntry* chosen = nullptr;
  if (!options.format.empty()) {
    for (const auto& entry : table) {
      if (entry.format == options.format) chosen = &entry;
    }
    if (chosen == nullptr) {
      throw Error(where + ": unknown motion format '" + options.format +
                  "' (formats: " + format_list() + ")");
    }
  } else {
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    for (const auto& entry : table) {
      if (std::find(entry.extensions.begin(), entry.extensions.end(), ext) !=
          entry.extensions.end()) {
        chosen = &entry;
      }
    }
    if (chosen == nullptr) {
      throw Error(where + ": cannot tell the motion format from the extension '" + ext +
                  "' (formats: " + format_list() + "; name one explicitly)");
    }
  }
  PositionClip clip = chosen->read(path, options);
  WHEELPOSE_CHECK(!clip.frames.empty());
  return clip;
}

}  // namespace wheelpose::motion
