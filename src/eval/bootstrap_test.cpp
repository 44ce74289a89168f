#include "eval/bootstrap.h"

#include <gtest/gtest.h>

#include "core/coco_test_fixtures.h"
#include "core/error.h"
#include "eval/coco_eval.h"

namespace wheelpose::eval {
namespace {

using coco::fixtures::gt_file;
using coco::fixtures::gt_person;
using coco::fixtures::json;
using coco::fixtures::json_list;
using coco::fixtures::kp_result;

const KeypointTemplate& coco17() {
  static const KeypointTemplate t = load_keypoint_template("coco17");
  return t;
}

struct Sets {
  coco::CocoGroundTruth gt;
  coco::CocoResults dt;
};

// Images 1..n, one person each; the first `found` images get a perfect detection (score 0.5),
// the others only a detection far from their person (score 0.9, a false positive).
Sets found_in(int images, int found) {
  std::vector<long> ids;
  std::vector<json> people, results;
  for (int i = 1; i <= images; ++i) {
    ids.push_back(i);
    people.push_back(gt_person(i, i, 100, 100, 10000));
    results.push_back(i <= found ? kp_result(i, 100, 100, 0.5) : kp_result(i, 900, 900, 0.9));
  }
  Sets s;
  s.gt = coco::parse_coco_gt(gt_file(ids, people), "gt.json", 17, true);
  s.dt = coco::parse_coco_results(json_list(results), "dt.json", s.gt, 17);
  return s;
}

double ap_with_weights(const Sets& s, const std::vector<int>& weights) {
  CocoEvaluator e(s.gt, s.dt, coco::IouType::kKeypoints, coco17());
  e.evaluate();
  e.accumulate(weights);
  return e.summarize().stats[0].value;
}

// Image 1 found, image 2 a false positive above its missed person: the precision curves are
// small enough to work out by hand (101 recall thresholds; every OKS threshold alike).
TEST(Bootstrap, WeightsCountAnImageThatManyTimes) {
  const Sets s = found_in(2, 1);
  EXPECT_DOUBLE_EQ(ap_with_weights(s, {1, 0}), 1.0);
  EXPECT_DOUBLE_EQ(ap_with_weights(s, {2, 0}), 1.0);
  EXPECT_DOUBLE_EQ(ap_with_weights(s, {0, 1}), 0.0);
  // FP then TP of 2 people: precision 0.5 up to recall 0.5 (thresholds 0 … 0.50).
  EXPECT_DOUBLE_EQ(ap_with_weights(s, {1, 1}), 51 * 0.5 / 101);
  // Two FPs then the TP of 3 people: precision 1/3 up to recall 1/3 (thresholds 0 … 0.33).
  EXPECT_NEAR(ap_with_weights(s, {1, 2}), 34.0 / 3 / 101, 1e-12);
  // No weights is every image once.
  EXPECT_DOUBLE_EQ(ap_with_weights(s, {}), ap_with_weights(s, {1, 1}));
  EXPECT_THROW(ap_with_weights(s, {1}), Error);
}

TEST(Bootstrap, PercentilesInterpolateLikeNumpy) {
  const std::vector<double> v = {1, 2, 3, 4};
  EXPECT_DOUBLE_EQ(percentile_of_sorted(v, 0), 1);
  EXPECT_DOUBLE_EQ(percentile_of_sorted(v, 0.25), 1.75);
  EXPECT_DOUBLE_EQ(percentile_of_sorted(v, 0.5), 2.5);
  EXPECT_DOUBLE_EQ(percentile_of_sorted(v, 1), 4);
  EXPECT_DOUBLE_EQ(percentile_of_sorted({7}, 0.975), 7);
}

TEST(Bootstrap, AModelAgainstItselfDiffersByExactlyNothing) {
  const Sets s = found_in(20, 14);
  BootstrapOptions options;
  options.samples = 200;
  const BootstrapResult r =
      bootstrap_ap(s.gt, s.dt, &s.dt, coco::IouType::kKeypoints, coco17(), options);
  ASSERT_EQ(r.difference.size(), 2u);
  for (const BootstrapInterval& d : r.difference) {
    EXPECT_EQ(d.low, 0.0);
    EXPECT_EQ(d.high, 0.0);
    EXPECT_EQ(d.estimate, 0.0);
  }
  EXPECT_EQ(r.ours[0].low, r.baseline[0].low);
  EXPECT_EQ(r.ours[0].high, r.baseline[0].high);
}

TEST(Bootstrap, TheIntervalSurroundsTheEstimateAndRepeatsForASeed) {
  const Sets s = found_in(20, 14);
  BootstrapOptions options;
  options.samples = 300;
  options.seed = 7;
  const BootstrapResult a =
      bootstrap_ap(s.gt, s.dt, nullptr, coco::IouType::kKeypoints, coco17(), options);
  ASSERT_EQ(a.ours.size(), 2u);
  EXPECT_TRUE(a.baseline.empty() && a.difference.empty());
  const BootstrapInterval& ap = a.ours[0];
  EXPECT_EQ(ap.key, "AP");
  EXPECT_DOUBLE_EQ(ap.estimate, ap_with_weights(s, {}));
  EXPECT_LT(ap.low, ap.estimate);
  EXPECT_GT(ap.high, ap.estimate);
  const BootstrapResult again =
      bootstrap_ap(s.gt, s.dt, nullptr, coco::IouType::kKeypoints, coco17(), options);
  EXPECT_EQ(again.ours[0].low, ap.low);
  EXPECT_EQ(again.ours[0].high, ap.high);
  options.seed = 8;
  const BootstrapResult other =
      bootstrap_ap(s.gt, s.dt, nullptr, coco::IouType::kKeypoints, coco17(), options);
  EXPECT_TRUE(other.ours[0].low != ap.low || other.ours[0].high != ap.high);
}

// One image: every resample is that image, so the interval is the value itself.
TEST(Bootstrap, OneImageHasNoSpread) {
  const Sets s = found_in(1, 1);
  BootstrapOptions options;
  options.samples = 50;
  const BootstrapResult r =
      bootstrap_ap(s.gt, s.dt, nullptr, coco::IouType::kKeypoints, coco17(), options);
  EXPECT_DOUBLE_EQ(r.ours[0].estimate, 1.0);  // 1 / (1 + eps), as pycocotools computes it
  EXPECT_EQ(r.ours[0].low, r.ours[0].estimate);
  EXPECT_EQ(r.ours[0].high, r.ours[0].estimate);
  const json j = bootstrap_json(r);
  EXPECT_EQ(j["ours"]["AP"]["low"], r.ours[0].estimate);
  EXPECT_EQ(j["samples"], 50);
  EXPECT_FALSE(j.contains("difference"));
  EXPECT_EQ(bootstrap_markdown(r),
            "| stat | ours |\n|---|---|\n| AP | 100.0 [100.0, 100.0] |\n"
            "| AP50 | 100.0 [100.0, 100.0] |\n");
}

}  // namespace
}  // namespace wheelpose::eval
