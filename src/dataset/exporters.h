#pragma once
// The table of label formats `wheelpose coco export --format` writes, by name: a new format is
// one function (beside export_yolo_pose in coco_tools.h) plus one line in exporters.cpp.

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "core/keypoint_template.h"
#include "dataset/coco_file.h"

namespace wheelpose::dataset {

struct DatasetExporter {
  const char* name;         // as given to --format
  const char* description;  // for --help
  // Writes the labels of `root` (read from `source`) under `out_dir`; returns the label lines.
  std::size_t (*write)(const json& root, const std::string& source,
                       const KeypointTemplate& keypoint_template,
                       const std::filesystem::path& out_dir);
};

const std::vector<DatasetExporter>& dataset_exporters();
std::vector<std::string> dataset_exporter_names();
// Looks an exporter up by name; throws Error listing the known names.
const DatasetExporter& dataset_exporter(const std::string& name);

}  // namespace wheelpose::dataset
