#include "dataset/exporters.h"

#include "core/error.h"
#include "dataset/coco_tools.h"

namespace wheelpose::dataset {

const std::vector<DatasetExporter>& dataset_exporters() {
  static const std::vector<DatasetExporter> exporters = {
      {"yolo-pose", "Ultralytics YOLO-pose labels and data.yaml", &export_yolo_pose},
  };
  return exporters;
}

std::vector<std::string> dataset_exporter_names() {
  std::vector<std::string> names;
  for (const DatasetExporter& e : dataset_exporters()) names.emplace_back(e.name);
  return names;
}

const DatasetExporter& dataset_exporter(const std::string& name) {
  std::string known;
  for (const DatasetExporter& exporter : dataset_exporters()) {
    if (exporter.name == name) return exporter;
    known += (known.empty() ? "" : ", ") + std::string(exporter.name);
  }
  throw Error("unknown label format '" + name + "' (known: " + known + ")");
}

}  // namespace wheelpose::dataset
