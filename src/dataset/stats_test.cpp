#include "dataset/stats.h"

#include <gtest/gtest.h>

namespace wheelpose::dataset {
namespace {

TEST(Histogram, BinsAndClampsToEnds) {
  Histogram h{0, 1, std::vector<std::int64_t>(4)};
  for (double v : {-3.0, 0.0, 0.3, 0.5, 0.99, 1.0, 7.0}) h.add(v);
  EXPECT_EQ(h.counts, (std::vector<std::int64_t>{2, 1, 1, 3}));
  EXPECT_EQ(h.total(), 7);
}

TEST(Grid, RowMajorFromTheTopLeftWithPeak) {
  Grid g{4, 2, std::vector<std::int64_t>(8)};
  g.add(0.9, 0.9);  // column 3, row 1
  g.add(0.9, 0.8);
  g.add(0.1, 0.1);  // column 0, row 0
  EXPECT_EQ(g.counts[1 * 4 + 3], 2);
  EXPECT_EQ(g.counts[0], 1);
  EXPECT_EQ(g.peak(), std::make_pair(3, 1));
}

TEST(ComputeStats, CountsWithoutKeypointsOrCamera) {
  const json root = json::parse(R"({
    "images": [{"id": 1, "file_name": "a", "width": 100, "height": 50},
               {"id": 2, "file_name": "b", "width": 100, "height": 50}],
    "categories": [{"id": 1, "name": "person"}],
    "annotations": [{"id": 1, "image_id": 1, "category_id": 1, "iscrowd": 0, "area": 1,
                     "bbox": [0, 0, 50, 25]},
                    {"id": 2, "image_id": 1, "category_id": 1, "iscrowd": 1, "area": 1,
                     "bbox": [0, 0, 5, 5]}]})");
  const DatasetStats s = compute_stats(root, "f", "f");
  EXPECT_EQ(s.images, 2);
  EXPECT_EQ(s.instances, 1);
  EXPECT_EQ(s.labelled_instances, 0);
  EXPECT_EQ(s.boxes_per_image, (std::vector<std::int64_t>{1}));
  EXPECT_EQ(s.box_size.counts[10], 1);  // sqrt(1250 / 5000) = 0.5
  EXPECT_FALSE(s.has_camera);
  EXPECT_EQ(s.camera_note, "no image has camera.extrinsics; camera analysis skipped");
}

}  // namespace
}  // namespace wheelpose::dataset
