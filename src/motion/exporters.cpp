#include "motion/exporters.h"

#include <sstream>

#include "core/error.h"
#include "motion/clip_json.h"
#include "motion/export_bvh.h"
#include "motion/export_fbx.h"
#include "motion/export_gltf.h"

namespace wheelpose::motion {

const std::vector<ClipExporter>& clip_exporters() {
  static const std::vector<ClipExporter> table = {
      {"json", ".json",
       [](const SeatedClip& c, const std::filesystem::path& p) { write_seated_clip_json(c, p); }},
      {"glb", ".glb",
       [](const SeatedClip& c, const std::filesystem::path& p) { write_glb(c.motion, p); }},
      {"bvh", ".bvh",
       [](const SeatedClip& c, const std::filesystem::path& p) { write_bvh(c.motion, p); }},
      {"fbx", ".fbx",
       [](const SeatedClip& c, const std::filesystem::path& p) { write_fbx(c.motion, p); }},
      // The same document as ASCII, for reading by eye and for tools that want text; Blender
      // reads only binary FBX.
      {"fbx-ascii", ".ascii.fbx",
       [](const SeatedClip& c, const std::filesystem::path& p) { write_fbx_ascii(c.motion, p); }},
  };
  return table;
}

const ClipExporter& clip_exporter(const std::string& name) {
  std::string known;
  for (const ClipExporter& exporter : clip_exporters()) {
    if (exporter.name == name) return exporter;
    known += (known.empty() ? "" : ", ") + std::string(exporter.name);
  }
  throw Error("unknown export format '" + name + "' (known: " + known + ")");
}

std::vector<const ClipExporter*> parse_exporter_list(const std::string& names) {
  std::vector<const ClipExporter*> result;
  std::stringstream stream(names);
  std::string name;
  while (std::getline(stream, name, ',')) {
    if (name.empty()) continue;
    const ClipExporter* exporter = &clip_exporter(name);
    for (const ClipExporter* existing : result) {
      if (existing == exporter) throw Error("export format '" + name + "' is listed twice");
    }
    result.push_back(exporter);
  }
  if (result.empty()) throw Error("no export formats given");
  return result;
}

}  // namespace wheelpose::motion
