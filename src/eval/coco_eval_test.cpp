#include "eval/coco_eval.h"

#include <gtest/gtest.h>

#include "core/coco_test_fixtures.h"
#include "eval/oks_iou.h"

namespace wheelpose::eval {
namespace {

using coco::fixtures::box_result;
using coco::fixtures::gt_file;
using coco::fixtures::gt_person;
using coco::fixtures::json;
using coco::fixtures::kp_result;

struct EvalRun {
  coco::CocoGroundTruth gt;
  coco::CocoResults dt;
  EvalSummary summary;
  double stat(const std::string& key) const {
    for (const auto& s : summary.stats) {
      if (s.key == key) return s.value;
    }
    ADD_FAILURE() << "no stat " << key;
    return -99;
  }
};

EvalRun evaluate(const json& gt_json, const std::vector<json>& results, coco::IouType type) {
  const KeypointTemplate coco = load_keypoint_template("coco17");
  EvalRun run;
  run.gt = coco::parse_coco_gt(gt_json, "gt.json", 17, type == coco::IouType::kKeypoints);
  run.dt = coco::parse_coco_results(coco::fixtures::json_list(results), "dt.json", run.gt, 17);
  run.summary = run_coco_eval(run.gt, run.dt, type, coco);
  return run;
}

TEST(CocoEvalTest, PerfectKeypointDetectionScoresOne) {
  const EvalRun r = evaluate(gt_file({1}, {gt_person(7, 1, 100, 100, 10000)}),
                             {kp_result(1, 100, 100, 0.9)}, coco::IouType::kKeypoints);
  EXPECT_DOUBLE_EQ(r.stat("AP"), 1.0);
  EXPECT_DOUBLE_EQ(r.stat("AP75"), 1.0);
  EXPECT_DOUBLE_EQ(r.stat("AR"), 1.0);
  EXPECT_DOUBLE_EQ(r.stat("APl"), 1.0);
  // No GT in the medium range: -1, as pycocotools reports empty selections.
  EXPECT_DOUBLE_EQ(r.stat("APm"), -1.0);
  EXPECT_DOUBLE_EQ(r.stat("ARm"), -1.0);
  // The summary's own lookup: the value, and nothing for −1 or a stat it does not have.
  EXPECT_EQ(r.summary.stat("AP"), r.stat("AP"));
  EXPECT_EQ(r.summary.stat("APm"), std::nullopt);
  EXPECT_EQ(r.summary.stat("APs"), std::nullopt);  // keypoint summaries have no small area
}

TEST(CocoEvalTest, SummaryTextMatchesPycocotoolsFormat) {
  const EvalRun r = evaluate(gt_file({1}, {gt_person(7, 1, 100, 100, 10000)}),
                             {kp_result(1, 100, 100, 0.9)}, coco::IouType::kKeypoints);
  const std::string expected =
      " Average Precision  (AP) @[ IoU=0.50:0.95 | area=   all | maxDets= 20 ] = 1.000\n"
      " Average Precision  (AP) @[ IoU=0.50      | area=   all | maxDets= 20 ] = 1.000\n"
      " Average Precision  (AP) @[ IoU=0.75      | area=   all | maxDets= 20 ] = 1.000\n"
      " Average Precision  (AP) @[ IoU=0.50:0.95 | area=medium | maxDets= 20 ] = -1.000\n"
      " Average Precision  (AP) @[ IoU=0.50:0.95 | area= large | maxDets= 20 ] = 1.000\n"
      " Average Recall     (AR) @[ IoU=0.50:0.95 | area=   all | maxDets= 20 ] = 1.000\n"
      " Average Recall     (AR) @[ IoU=0.50      | area=   all | maxDets= 20 ] = 1.000\n"
      " Average Recall     (AR) @[ IoU=0.75      | area=   all | maxDets= 20 ] = 1.000\n"
      " Average Recall     (AR) @[ IoU=0.50:0.95 | area=medium | maxDets= 20 ] = -1.000\n"
      " Average Recall     (AR) @[ IoU=0.50:0.95 | area= large | maxDets= 20 ] = 1.000\n";
  EXPECT_EQ(r.summary.text, expected);
}

TEST(CocoEvalTest, BboxSummaryHasTwelveStatsWithMaxDets) {
  const EvalRun r = evaluate(gt_file({1}, {gt_person(7, 1, 100, 100, 500)}),
                             {box_result(1, 100, 100, 40, 80, 0.9)}, coco::IouType::kBbox);
  ASSERT_EQ(r.summary.stats.size(), 12u);
  EXPECT_NE(r.summary.text.find(
                " Average Recall     (AR) @[ IoU=0.50:0.95 | area= small | maxDets=100 ] = 1.000"),
            std::string::npos);
  EXPECT_NE(r.summary.text.find("maxDets=  1 ] = 1.000"), std::string::npos);
  // GT `area` (500), not the 40x80 box, decides the bucket: small only.
  EXPECT_DOUBLE_EQ(r.stat("APs"), 1.0);
  EXPECT_DOUBLE_EQ(r.stat("APm"), -1.0);
}

TEST(CocoEvalTest, AreaBoundsAreInclusive) {
  // 96^2 lies in both medium and large; 32^2 in both small and medium (bbox).
  const EvalRun k = evaluate(gt_file({1}, {gt_person(7, 1, 100, 100, 96.0 * 96.0)}),
                             {kp_result(1, 100, 100, 0.9)}, coco::IouType::kKeypoints);
  EXPECT_DOUBLE_EQ(k.stat("APm"), 1.0);
  EXPECT_DOUBLE_EQ(k.stat("APl"), 1.0);
  const EvalRun b = evaluate(gt_file({1}, {gt_person(7, 1, 100, 100, 32.0 * 32.0)}),
                             {box_result(1, 100, 100, 40, 80, 0.9)}, coco::IouType::kBbox);
  EXPECT_DOUBLE_EQ(b.stat("APs"), 1.0);
  EXPECT_DOUBLE_EQ(b.stat("APm"), 1.0);
  EXPECT_DOUBLE_EQ(b.stat("APl"), -1.0);
}

TEST(CocoEvalTest, OnlyTwentyKeypointDetectionsPerImageCount) {
  // 21 people, 21 perfect detections with falling scores: the 21st is cut by maxDets=20.
  std::vector<json> anns, dets;
  for (int i = 0; i < 21; ++i) {
    anns.push_back(gt_person(100 + i, 1, 100.0 * i, 100, 10000));
    dets.push_back(kp_result(1, 100.0 * i, 100, 1.0 - 0.01 * i));
  }
  const EvalRun r = evaluate(gt_file({1}, anns), dets, coco::IouType::kKeypoints);
  EXPECT_DOUBLE_EQ(r.stat("AR"), 20.0 / 21.0);
  // Precision 1 up to recall 20/21 = 0.952: recall thresholds 0.00..0.95 = 96 of 101.
  EXPECT_NEAR(r.stat("AP"), 96.0 / 101.0, 1e-12);
}

TEST(CocoEvalTest, BboxMaxDetsOneAndTen) {
  std::vector<json> anns, dets;
  for (int i = 0; i < 12; ++i) {
    anns.push_back(gt_person(100 + i, 1, 100.0 * i, 100, 10000));
    dets.push_back(box_result(1, 100.0 * i, 100, 40, 80, 1.0 - 0.01 * i));
  }
  const EvalRun r = evaluate(gt_file({1}, anns), dets, coco::IouType::kBbox);
  EXPECT_DOUBLE_EQ(r.stat("AR1"), 1.0 / 12.0);
  EXPECT_DOUBLE_EQ(r.stat("AR10"), 10.0 / 12.0);
  EXPECT_DOUBLE_EQ(r.stat("AR100"), 1.0);
}

TEST(CocoEvalTest, ScoreTiesKeepFileOrder) {
  // One GT, two detections with equal score: one perfect, one far away (a false positive).
  const json gt = gt_file({1}, {gt_person(7, 1, 100, 100, 10000)});
  const EvalRun tp_first = evaluate(gt, {kp_result(1, 100, 100, 0.5), kp_result(1, 400, 100, 0.5)},
                                    coco::IouType::kKeypoints);
  EXPECT_DOUBLE_EQ(tp_first.stat("AP"), 1.0);
  // FP first: precision [0, 0.5] -> interpolated 0.5 at every recall threshold.
  const EvalRun fp_first = evaluate(gt, {kp_result(1, 400, 100, 0.5), kp_result(1, 100, 100, 0.5)},
                                    coco::IouType::kKeypoints);
  EXPECT_NEAR(fp_first.stat("AP"), 0.5, 1e-12);
}

TEST(CocoEvalTest, AnnotationIdZeroCountsAsUnmatchedLikePycocotools) {
  // pycocotools stores the matched GT id in dtm and tests dtm != 0, so a match to GT id 0 is a
  // false positive while the GT still counts: AP = AR = 0.
  const EvalRun zero = evaluate(gt_file({1}, {gt_person(0, 1, 100, 100, 10000)}),
                                {kp_result(1, 100, 100, 0.9)}, coco::IouType::kKeypoints);
  EXPECT_DOUBLE_EQ(zero.stat("AP"), 0.0);
  EXPECT_DOUBLE_EQ(zero.stat("AR"), 0.0);
  const EvalRun five = evaluate(gt_file({1}, {gt_person(5, 1, 100, 100, 10000)}),
                                {kp_result(1, 100, 100, 0.9)}, coco::IouType::kKeypoints);
  EXPECT_DOUBLE_EQ(five.stat("AP"), 1.0);
}

TEST(CocoEvalTest, DetectionsOnImageWithoutGtAreFalsePositives) {
  // Image 2 has no GT; its higher-scored detection comes first: precision [0, 0.5].
  const EvalRun r = evaluate(gt_file({1, 2}, {gt_person(7, 1, 100, 100, 10000)}),
                             {kp_result(1, 100, 100, 0.5), kp_result(2, 100, 100, 0.9)},
                             coco::IouType::kKeypoints);
  EXPECT_NEAR(r.stat("AP"), 0.5, 1e-12);
  EXPECT_DOUBLE_EQ(r.stat("AR"), 1.0);
}

TEST(CocoEvalTest, GtImageWithoutDetectionsLowersRecall) {
  const EvalRun r = evaluate(
      gt_file({1, 2}, {gt_person(7, 1, 100, 100, 10000), gt_person(8, 2, 100, 100, 10000)}),
      {kp_result(1, 100, 100, 0.9)}, coco::IouType::kKeypoints);
  EXPECT_DOUBLE_EQ(r.stat("AR"), 0.5);
  EXPECT_NEAR(r.stat("AP"), 51.0 / 101.0, 1e-12);  // recall thresholds 0.00..0.50
}

TEST(CocoEvalTest, CrowdGtAbsorbsBoxDetectionsWithoutPenalty) {
  // A crowd box plus one person. Two detections inside the crowd region match it (IoU =
  // intersection / detection area = 1) and are ignored, not false positives.
  json crowd = gt_person(9, 1, 0, 0, 90000);
  crowd["bbox"] = {0, 0, 300, 300};
  crowd["iscrowd"] = 1;
  const EvalRun r =
      evaluate(gt_file({1}, {gt_person(7, 1, 500, 100, 10000), crowd}),
               {box_result(1, 10, 10, 20, 20, 0.99), box_result(1, 50, 50, 20, 20, 0.98),
                box_result(1, 500, 100, 40, 80, 0.5)},
               coco::IouType::kBbox);
  EXPECT_DOUBLE_EQ(r.stat("AP"), 1.0);
  EXPECT_DOUBLE_EQ(r.stat("AR100"), 1.0);
}

TEST(CocoEvalTest, CrowdAndZeroKeypointGtAreIgnoredForKeypoints) {
  json crowd = gt_person(9, 1, 300, 100, 10000);
  crowd["iscrowd"] = 1;
  // num_keypoints == 0 ignores the GT even though its keypoints are labelled: the field rules.
  json unlabelled = gt_person(10, 1, 600, 100, 10000);
  unlabelled["num_keypoints"] = 0;
  const EvalRun r = evaluate(
      gt_file({1}, {gt_person(7, 1, 100, 100, 10000), crowd, unlabelled}),
      {kp_result(1, 300, 100, 0.99), kp_result(1, 600, 100, 0.98), kp_result(1, 100, 100, 0.5)},
      coco::IouType::kKeypoints);
  EXPECT_DOUBLE_EQ(r.stat("AP"), 1.0);
  EXPECT_DOUBLE_EQ(r.stat("AR"), 1.0);
  // With only ignored GT, the category is empty: -1.
  const EvalRun empty =
      evaluate(gt_file({1}, {crowd}), {kp_result(1, 300, 100, 0.9)}, coco::IouType::kKeypoints);
  EXPECT_DOUBLE_EQ(empty.stat("AP"), -1.0);
}

TEST(CocoEvalTest, UnmatchedDetectionOutsideAreaRangeIsIgnored) {
  // A medium GT (area 2000) matched, plus a far false positive whose keypoint extent is large
  // (> 96^2): for the medium range it is ignored, for "all" it counts.
  json big = kp_result(1, 1000, 100, 0.9);
  for (int i = 0; i < 17; ++i) {
    big["keypoints"][3 * i] = 1000.0 + 10.0 * i;
    big["keypoints"][3 * i + 1] = 100.0 + 10.0 * i;
  }
  const EvalRun r = evaluate(gt_file({1}, {gt_person(7, 1, 100, 100, 2000)}),
                             {big, kp_result(1, 100, 100, 0.5)}, coco::IouType::kKeypoints);
  EXPECT_NEAR(r.stat("AP"), 0.5, 1e-12);
  EXPECT_DOUBLE_EQ(r.stat("APm"), 1.0);
}

TEST(OksTest, LabelledKeypointsOnly) {
  const KeypointTemplate coco = load_keypoint_template("coco17");
  coco::GtAnnotation g;
  g.area = 400;
  g.bbox = {0, 0, 20, 20};
  g.keypoints.assign(51, 0.0);
  g.keypoints[0] = 10;
  g.keypoints[1] = 10;
  g.keypoints[2] = 1;                 // occluded but labelled: counts like visible
  std::vector<double> dt(51, 500.0);  // unlabelled points far away do not matter
  dt[0] = 13;
  dt[1] = 14;
  EXPECT_NEAR(compute_oks(g, dt, oks_vars(coco)), 9.569279308308938e-06, 1e-18);
}

TEST(OksTest, ZeroKeypointGtUsesDistanceToGrownBox) {
  const KeypointTemplate coco = load_keypoint_template("coco17");
  coco::GtAnnotation g;
  g.area = 2500;
  g.bbox = {100, 100, 50, 50};  // grown box [50, 200] x [50, 200]
  g.keypoints.assign(51, 0.0);
  std::vector<double> dt;
  for (int i = 0; i < 17; ++i) dt.insert(dt.end(), {210.0, 100.0, 1.0});  // 10 px right of it
  EXPECT_NEAR(compute_oks(g, dt, oks_vars(coco)), 0.3311144222847988, 1e-15);
  for (int i = 0; i < 17; ++i) dt[3 * i] = 199;  // inside: distance 0
  EXPECT_DOUBLE_EQ(compute_oks(g, dt, oks_vars(coco)), 1.0);
}

TEST(IouTest, CrowdUsesDetectionAreaAsUnion) {
  const coco::Box gt{0, 0, 10, 10}, dt{5, 0, 10, 10};
  EXPECT_DOUBLE_EQ(bbox_iou(dt, gt, false), 50.0 / 150.0);
  EXPECT_DOUBLE_EQ(bbox_iou(dt, gt, true), 50.0 / 100.0);
  EXPECT_DOUBLE_EQ(bbox_iou(coco::Box{20, 20, 5, 5}, gt, false), 0.0);
}

TEST(NumpySumTest, PairwiseOrder) {
  std::vector<double> v(300);
  for (int i = 0; i < 300; ++i) v[i] = 0.1 * (i % 7) + 1e-3 * i;
  double plain = 0;
  for (double x : v) plain += x;
  EXPECT_NEAR(numpy_sum(v.data(), v.size()), plain, 1e-9);
  const double three[3] = {1, 2, 3};
  EXPECT_DOUBLE_EQ(numpy_sum(three, 3), 6.0);
}

TEST(ParamsTest, ThresholdsAsNumpyLinspace) {
  const EvalParams p = EvalParams::for_type(coco::IouType::kKeypoints);
  ASSERT_EQ(p.iou_thresholds.size(), 10u);
  ASSERT_EQ(p.recall_thresholds.size(), 101u);
  EXPECT_EQ(p.iou_thresholds[5], 0.75);  // summarize() looks .75 up by exact equality
  EXPECT_EQ(p.recall_thresholds[100], 1.0);
  EXPECT_EQ(p.recall_thresholds[7], 7 * 0.01);
}

}  // namespace
}  // namespace wheelpose::eval
