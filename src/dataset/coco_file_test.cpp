#include "dataset/coco_file.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "core/error.h"

namespace wheelpose::dataset {
namespace {

TEST(CanonicalCoco, SortsArraysAndKeysOneElementPerLine) {
  const json root = json::parse(R"({
    "images": [{"id": 2, "file_name": "b.png"}, {"id": 1, "file_name": "a.png"}],
    "annotations": [{"id": 5, "image_id": 2, "bbox": [1.5, 2, 3.25, 4.0]},
                    {"id": 9, "image_id": 1}, {"id": 3, "image_id": 2}],
    "categories": [],
    "info": {"year": 2024, "description": "x"}})");
  EXPECT_EQ(canonical_coco_text(root),
            "{\n"
            "\"annotations\": [\n"
            "{\"id\":9,\"image_id\":1},\n"
            "{\"id\":3,\"image_id\":2},\n"
            "{\"bbox\":[1.5,2,3.25,4.0],\"id\":5,\"image_id\":2}\n"
            "],\n"
            "\"categories\": [],\n"
            "\"images\": [\n"
            "{\"file_name\":\"a.png\",\"id\":1},\n"
            "{\"file_name\":\"b.png\",\"id\":2}\n"
            "],\n"
            "\"info\": {\"description\":\"x\",\"year\":2024}\n"
            "}\n");
  // A fixed point: parsing and writing again gives the same bytes.
  const std::string once = canonical_coco_text(root);
  EXPECT_EQ(canonical_coco_text(json::parse(once)), once);
}

TEST(CanonicalCoco, StreamedMemberByMemberGivesTheSameBytes) {
  const json root = json::parse(R"({
    "annotations": [{"id": 1, "image_id": 1, "bbox": [0.5, 1, 2, 3]}, {"id": 2, "image_id": 1}],
    "categories": [{"id": 1, "name": "person"}], "images": [], "info": {"year": 2026},
    "licenses": []})");
  std::string streamed;
  CanonicalCocoWriter writer([&streamed](const std::string& text) { streamed += text; });
  writer.begin_array("annotations");
  for (const json& a : root["annotations"]) writer.element(a);
  writer.end_array();
  writer.member("categories", root["categories"]);
  writer.begin_array("images");
  writer.end_array();
  writer.member("info", root["info"]);
  writer.member("licenses", json::array());
  writer.finish();
  EXPECT_EQ(streamed, canonical_coco_text(root));
}

TEST(CocoInteger, AcceptsIntegralFloatsOnly) {
  EXPECT_EQ(as_integer(json(785)), 785);
  EXPECT_EQ(as_integer(json(785.0)), 785);
  EXPECT_FALSE(as_integer(json(785.5)));
  EXPECT_FALSE(as_integer(json("785")));
}

TEST(ValidateCoco, StructureVersusMeaning) {
  const json root = json::parse(R"({
    "images": [{"id": 1, "file_name": "a.png", "width": 10, "height": 10}],
    "categories": [{"id": 1, "name": "person", "keypoints": ["a", "b"], "skeleton": [[1, 3]]}],
    "annotations": [{"id": 1, "image_id": 1, "category_id": 1, "iscrowd": 0, "area": 4,
                     "bbox": [1, 1, 2, 2], "num_keypoints": 2,
                     "keypoints": [1, 1, 2, 11, 1, 1],
                     "segmentation": [[1, 1, 2, 2]]}]})");
  const auto problems = validate_coco(root);
  ASSERT_EQ(problems.size(), 3u);
  EXPECT_EQ(problems[0].path, "categories[0].skeleton[0]");
  EXPECT_EQ(problems[0].message, "keypoint index 3 is outside 1..2");
  EXPECT_EQ(problems[1].path, "annotations[0].segmentation[0]");
  EXPECT_EQ(problems[1].severity, Problem::Severity::kStructure);
  EXPECT_EQ(problems[2].path, "annotations[0].keypoints[1] (b)");
  EXPECT_EQ(problems[2].severity, Problem::Severity::kMeaning);
  EXPECT_THROW(require_usable(root, "f.json"), Error);
}

}  // namespace
}  // namespace wheelpose::dataset
