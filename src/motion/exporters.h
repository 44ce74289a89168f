#pragma once
// The table of seated-clip output formats, by name: a new format is one function plus one line.

#include <filesystem>
#include <string>
#include <vector>

#include "motion/clip.h"

namespace wheelpose::motion {

struct ClipExporter {
  const char* name;       // as given to --exports
  const char* extension;  // file written: <dir>/<clip name><extension>
  void (*write)(const SeatedClip& clip, const std::filesystem::path& path);
};

const std::vector<ClipExporter>& clip_exporters();
// Looks an exporter up by name; throws Error listing the known names.
const ClipExporter& clip_exporter(const std::string& name);
// Parses "json,glb,bvh" into exporters, rejecting unknown and duplicate names.
std::vector<const ClipExporter*> parse_exporter_list(const std::string& names);

}  // namespace wheelpose::motion
