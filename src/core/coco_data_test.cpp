#include "core/coco_data.h"

#include <gtest/gtest.h>

#include <functional>

#include "core/coco_test_fixtures.h"
#include "core/error.h"

namespace wheelpose::coco {
namespace {

using fixtures::gt_file;
using fixtures::gt_person;
using fixtures::json;
using fixtures::json_list;
using fixtures::kp_result;

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    EXPECT_EQ(e.exit_code(), 2);
    return e.what();
  }
  ADD_FAILURE() << "no error";
  return "";
}

CocoGroundTruth sample_gt() {
  return parse_coco_gt(gt_file({3, 1}, {gt_person(7, 1, 100, 100, 10000)}), "gt.json", 17, true);
}

TEST(CocoDataTest, GtImagesSortedAndIndexed) {
  const CocoGroundTruth gt = sample_gt();
  ASSERT_EQ(gt.images.size(), 2u);
  EXPECT_EQ(gt.images[0].id, 1);
  EXPECT_EQ(gt.image_position(3), 1);
  EXPECT_EQ(gt.image_position(2), -1);
  EXPECT_EQ(gt.annotations[0].num_keypoints, 17);
  EXPECT_FALSE(gt.annotations[0].iscrowd);
}

TEST(CocoDataTest, KeypointResultsTakeAreaAndBoxFromKeypointExtent) {
  // loadRes keypoint branch: bbox = extent of all keypoints, area = its w * h; ids from 1.
  const CocoResults r =
      parse_coco_results(json_list({kp_result(1, 100, 100, 0.5)}), "dt.json", sample_gt(), 17);
  ASSERT_EQ(r.detections.size(), 1u);
  EXPECT_EQ(r.detections[0].id, 1);
  // person_keypoints: x from 100 to 132, y from 100 to 164.
  EXPECT_DOUBLE_EQ(r.detections[0].bbox.w, 32.0);
  EXPECT_DOUBLE_EQ(r.detections[0].bbox.h, 64.0);
  EXPECT_DOUBLE_EQ(r.detections[0].area, 32.0 * 64.0);
}

TEST(CocoDataTest, ResultsWithBoxUseBoxAreaEvenWithKeypoints) {
  // Detectron2 writes keypoint results with a bbox: loadRes then takes the bbox branch.
  json d = kp_result(1, 100, 100, 0.5);
  d["bbox"] = {90, 95, 50, 80};
  const CocoResults r = parse_coco_results(json_list({d}), "dt.json", sample_gt(), 17);
  EXPECT_DOUBLE_EQ(r.detections[0].area, 4000.0);
  EXPECT_TRUE(r.has_keypoints);
  // A later entry without bbox is then an error, as in pycocotools.
  const std::string e = error_of([&] {
    parse_coco_results(json_list({d, kp_result(1, 0, 0, 0.4)}), "dt.json", sample_gt(), 17);
  });
  EXPECT_NE(e.find("dt.json: results[1]: missing field 'bbox'"), std::string::npos) << e;
}

TEST(CocoDataTest, IntegralFloatIdsAreAccepted) {
  json d = kp_result(1, 100, 100, 0.5);
  d["image_id"] = 1.0;
  EXPECT_EQ(parse_coco_results(json_list({d}), "dt.json", sample_gt(), 17).detections[0].image_id,
            1);
  d["image_id"] = 1.5;
  EXPECT_NE(error_of([&] {
              parse_coco_results(json_list({d}), "dt.json", sample_gt(), 17);
            }).find("results[0].image_id: expected an integer"),
            std::string::npos);
}

TEST(CocoDataTest, GtErrorsNameEntryAndField) {
  json no_num = gt_person(7, 1, 100, 100, 10000);
  no_num.erase("num_keypoints");
  EXPECT_NE(error_of([&] {
              parse_coco_gt(gt_file({1}, {no_num}), "gt.json", 17, true);
            }).find("gt.json: annotations[0]: missing field 'num_keypoints'"),
            std::string::npos);
  // Box-only evaluation does not need keypoint fields.
  EXPECT_NO_THROW(parse_coco_gt(gt_file({1}, {no_num}), "gt.json", 17, false));
  EXPECT_NE(error_of([&] {
              parse_coco_gt(gt_file({1}, {gt_person(7, 1, 0, 0, 1), gt_person(7, 1, 0, 0, 1)}),
                            "gt.json", 17, true);
            }).find("gt.json: annotations[1].id: duplicate annotation id 7"),
            std::string::npos);
  json bad_area = gt_person(7, 1, 0, 0, 1);
  bad_area["area"] = "big";
  EXPECT_NE(error_of([&] {
              parse_coco_gt(gt_file({1}, {bad_area}), "gt.json", 17, true);
            }).find("gt.json: annotations[0].area: expected a number"),
            std::string::npos);
  json no_cats = gt_file({1}, {});
  no_cats["categories"] = json::array();
  EXPECT_NE(error_of([&] { parse_coco_gt(no_cats, "gt.json", 17, true); }).find("no categories"),
            std::string::npos);
}

TEST(CocoDataTest, RequireKeypointsNamesFirstMissingEntry) {
  json box = fixtures::box_result(1, 0, 0, 10, 10, 0.3);
  const CocoResults r = parse_coco_results(json_list({box, box}), "dt.json", sample_gt(), 17);
  EXPECT_FALSE(r.has_keypoints);
  EXPECT_NO_THROW(require_fields(r, IouType::kBbox));
  EXPECT_NE(error_of([&] {
              require_fields(r, IouType::kKeypoints);
            }).find("dt.json: results[0]: missing field 'keypoints'"),
            std::string::npos);
}

}  // namespace
}  // namespace wheelpose::coco
