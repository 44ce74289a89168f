#include "eval/keypoint_metrics.h"

#include <gtest/gtest.h>

#include "core/coco_test_fixtures.h"
#include "core/error.h"

namespace wheelpose::eval {
namespace {

using coco::fixtures::gt_file;
using coco::fixtures::gt_person;
using coco::fixtures::json;
using coco::fixtures::json_list;
using coco::fixtures::kp_result;

class KeypointMetricsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    coco_ = load_keypoint_template("coco17");
    // GT 7 in image 1 (box 40 x 80, diagonal 89.44, so PDJ@5 radius 4.47 px; area 10000) with
    // right_eye unlabelled; GT 8 in image 2 is never detected.
    json first = gt_person(7, 1, 100, 100, 10000);
    first["keypoints"][3 * 2 + 2] = 0;
    first["num_keypoints"] = 16;
    gt_ = coco::parse_coco_gt(gt_file({1, 2}, {first, gt_person(8, 2, 100, 100, 10000)}), "gt.json",
                              17, true);
    // The detection is exact except nose (3, 4) -> 5 px and left_eye (3, 0) -> 3 px; a second,
    // far detection in image 1 is a false positive and must not form a pair.
    json det = kp_result(1, 100, 100, 0.9);
    det["keypoints"][0] = 103.0;
    det["keypoints"][1] = 104.0;
    det["keypoints"][3] = 105.0;
    dt_ = coco::parse_coco_results(json_list({det, kp_result(1, 600, 100, 0.95)}), "dt.json", gt_,
                                   17);
  }
  KeypointTemplate coco_;
  coco::CocoGroundTruth gt_;
  coco::CocoResults dt_;
};

TEST_F(KeypointMetricsTest, HandComputedPair) {
  CocoEvaluator evaluator(gt_, dt_, coco::IouType::kKeypoints, coco_);
  evaluator.evaluate();
  const KeypointMetrics m = compute_keypoint_metrics(evaluator, gt_, dt_, coco_);
  EXPECT_EQ(m.gt_people, 2);
  EXPECT_EQ(m.pairs, 1);
  EXPECT_EQ(m.missed_people, 1);

  const KeypointStats& nose = m.keypoints[0];
  EXPECT_EQ(nose.count, 1);
  EXPECT_DOUBLE_EQ(*nose.pjpe, 5.0);
  EXPECT_DOUBLE_EQ(*nose.pdj5, 0.0);  // 5 px >= 4.47 px
  // exp(-25 / 0.052^2 / 10000 / 2) = 0.630: above 0.5, below 0.75.
  EXPECT_DOUBLE_EQ(*nose.oks50, 1.0);
  EXPECT_DOUBLE_EQ(*nose.oks75, 0.0);
  EXPECT_EQ(nose.missed, 1);

  const KeypointStats& left_eye = m.keypoints[1];
  EXPECT_DOUBLE_EQ(*left_eye.pjpe, 3.0);
  EXPECT_DOUBLE_EQ(*left_eye.pdj5, 1.0);
  EXPECT_DOUBLE_EQ(*left_eye.oks75, 1.0);  // exp(-0.18) = 0.835

  const KeypointStats& right_eye = m.keypoints[2];  // unlabelled in the matched GT
  EXPECT_EQ(right_eye.count, 0);
  EXPECT_FALSE(right_eye.pjpe.has_value());
  EXPECT_EQ(right_eye.missed, 1);

  EXPECT_EQ(m.overall.count, 16);
  EXPECT_DOUBLE_EQ(*m.overall.pjpe, 0.5);
  EXPECT_DOUBLE_EQ(*m.overall.pdj5, 15.0 / 16.0);
  EXPECT_DOUBLE_EQ(*m.overall.oks50, 1.0);
  EXPECT_DOUBLE_EQ(*m.overall.oks75, 15.0 / 16.0);

  const KeypointStats* head = nullptr;
  for (const auto& g : m.groups) {
    if (g.name == "head") head = &g;
  }
  ASSERT_NE(head, nullptr);
  EXPECT_EQ(head->count, 4);
  EXPECT_DOUBLE_EQ(*head->pjpe, 2.0);
  EXPECT_DOUBLE_EQ(*head->pdj5, 0.75);
  EXPECT_EQ(head->missed, 5);
}

TEST_F(KeypointMetricsTest, PairsAreTheCocoMatchesOnly) {
  CocoEvaluator evaluator(gt_, dt_, coco::IouType::kKeypoints, coco_);
  evaluator.evaluate();
  const auto pairs = matched_pairs(evaluator, gt_);
  ASSERT_EQ(pairs.size(), 2u);
  EXPECT_EQ(pairs[0], std::make_pair(0, 0));   // GT 7 with the 0.9 detection, not the 0.95 one
  EXPECT_EQ(pairs[1], std::make_pair(1, -1));  // GT 8 missed
}

TEST(KeypointTemplateTest, BuiltInCoco17) {
  const KeypointTemplate t = load_keypoint_template("coco17");
  ASSERT_EQ(t.size(), 17);
  EXPECT_EQ(t.keypoints[0].name, "nose");
  EXPECT_DOUBLE_EQ(t.keypoints[11].sigma, 0.107);
  EXPECT_EQ(t.skeleton.size(), 19u);
  EXPECT_EQ(t.skeleton[0], std::make_pair(15, 13));  // [16, 14] 1-based
  EXPECT_EQ(t.flip_pairs.size(), 8u);
  EXPECT_EQ(t.index_of("right_ankle"), 16);
}

TEST(KeypointTemplateTest, RejectsBadFiles) {
  EXPECT_THROW(parse_keypoint_template("{", "t.json"), Error);
  EXPECT_THROW(parse_keypoint_template(R"({"keypoints": [{"name": "a", "sigma": 0}]})", "t.json"),
               Error);
  EXPECT_THROW(
      parse_keypoint_template(
          R"({"keypoints": [{"name": "a", "sigma": 0.1}], "skeleton": [[1, 2]]})", "t.json"),
      Error);
  try {
    parse_keypoint_template(
        R"({"keypoints": [{"name": "a", "sigma": 0.1}], "flip_pairs": [["a", "b"]]})", "t.json");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("t.json: flip_pairs[0]: unknown keypoint 'b'"),
              std::string::npos)
        << e.what();
  }
  // Extra per-keypoint fields are allowed for later extensions.
  EXPECT_EQ(parse_keypoint_template(
                R"({"keypoints": [{"name": "a", "sigma": 0.1, "occlusion_tolerance": 2}]})", "t")
                .size(),
            1);
}

}  // namespace
}  // namespace wheelpose::eval
