#include "dataset/coco_tools.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "core/error.h"

namespace wheelpose::dataset {
namespace {

// `n` 10x10 images without categories' keypoints; annotation i on image i.
json images_only(int n) {
  json root = {{"images", json::array()},
               {"annotations", json::array()},
               {"categories", {{{"id", 1}, {"name", "person"}}}}};
  for (int i = 1; i <= n; ++i) {
    root["images"].push_back(
        {{"id", i * 10}, {"file_name", std::to_string(i) + ".png"}, {"width", 10}, {"height", 10}});
    root["annotations"].push_back({{"id", i},
                                   {"image_id", i * 10},
                                   {"category_id", 1},
                                   {"iscrowd", 0},
                                   {"area", 4},
                                   {"bbox", {1, 1, 2, 2}}});
  }
  return root;
}

std::vector<int> ids(const json& root) {
  std::vector<int> out;
  for (const json& im : root["images"]) out.push_back(im["id"]);
  std::sort(out.begin(), out.end());
  return out;
}

TEST(SampleCoco, EvenEndpointsAndSingle) {
  const json root = images_only(7);
  // round(i * 6 / 2) for i = 0..2 -> positions 0, 3, 6.
  EXPECT_EQ(ids(sample_coco(root, "x", 3, true, 0)), (std::vector<int>{10, 40, 70}));
  EXPECT_EQ(ids(sample_coco(root, "x", 1, true, 0)), (std::vector<int>{10}));
  EXPECT_EQ(ids(sample_coco(root, "x", 7, false, 5)).size(), 7u);
  EXPECT_THROW(sample_coco(root, "x", 0, true, 0), Error);
}

TEST(SplitCoco, AnnotationMotionIdsLinkImages) {
  json root = images_only(6);
  // Images 10 and 60 share a clip through their annotations; 20 and 30 through the image field.
  root["annotations"][0]["motion_id"] = 4;
  root["annotations"][5]["motion_id"] = 4;
  root["images"][1]["motion_id"] = "walk";
  root["images"][2]["motion_id"] = "walk";
  for (std::uint64_t seed = 0; seed < 20; ++seed) {
    const auto parts = split_coco(root, {0.5, 0.5}, {"a", "b"}, GroupBy::kMotion, seed);
    ASSERT_EQ(parts.size(), 2u);
    for (const auto& part : parts) {
      const auto in = ids(part.root);
      const std::set<int> s(in.begin(), in.end());
      EXPECT_EQ(s.count(10), s.count(60)) << "seed " << seed;
      EXPECT_EQ(s.count(20), s.count(30)) << "seed " << seed;
      EXPECT_EQ(part.root["annotations"].size(), in.size());
    }
    EXPECT_EQ(ids(parts[0].root).size() + ids(parts[1].root).size(), 6u);
  }
  // By image, 6 images at 0.5/0.5 split 3/3.
  const auto by_image = split_coco(root, {1, 1}, {"a", "b"}, GroupBy::kImage, 1);
  EXPECT_EQ(by_image[0].root["images"].size(), 3u);
}

TEST(MergeCoco, RenumbersInInputOrder) {
  const json a = images_only(2), b = [] {
    json r = images_only(3);
    for (json& im : r["images"]) im["file_name"] = "b" + im["file_name"].get<std::string>();
    return r;
  }();
  const json m = merge_coco({{"a", a}, {"b", b}}, false);
  EXPECT_EQ(ids(m), (std::vector<int>{1, 2, 3, 4, 5}));
  EXPECT_EQ(m["images"][2]["file_name"], "b1.png");
  EXPECT_EQ(m["annotations"][4]["image_id"], 5);
  EXPECT_EQ(m["annotations"][4]["id"], 5);
}

}  // namespace
}  // namespace wheelpose::dataset
