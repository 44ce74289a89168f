#include "dataset/exporters.h"

#include <gtest/gtest.h>

#include <set>
#include <string>

#include "core/error.h"
#include "dataset/coco_tools.h"

namespace wheelpose::dataset {
namespace {

TEST(DatasetExporters, NamesAreUniqueAndFoundByName) {
  std::set<std::string> seen;
  for (const DatasetExporter& e : dataset_exporters()) {
    EXPECT_TRUE(seen.insert(e.name).second) << e.name;
    EXPECT_EQ(&dataset_exporter(e.name), &e);
    EXPECT_NE(e.write, nullptr) << e.name;
  }
  EXPECT_EQ(dataset_exporter("yolo-pose").write, &export_yolo_pose);
  EXPECT_EQ(dataset_exporter_names().size(), dataset_exporters().size());
}

TEST(DatasetExporters, UnknownNameListsTheKnownOnes) {
  try {
    dataset_exporter("voc");
    FAIL() << "found";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("unknown label format 'voc' (known: yolo-pose"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace wheelpose::dataset
