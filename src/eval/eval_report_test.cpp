#include "eval/eval_report.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/coco_test_fixtures.h"
#include "core/keypoint_template.h"
#include "eval/eval_viz.h"

namespace wheelpose::eval {
namespace {

KeypointMetrics metrics(double pdj, double pjpe) {
  KeypointMetrics m;
  m.gt_people = 2;
  m.pairs = 1;
  m.missed_people = 1;
  KeypointStats s;
  s.name = "nose";
  s.count = 4;
  s.missed = 1;
  s.pdj5 = pdj;
  s.pjpe = pjpe;
  s.oks50 = 0.5;
  s.oks75 = 0.25;
  m.keypoints = {s};
  m.groups = {s};
  s.name = "all";
  m.overall = s;
  return m;
}

ResultReport report(double ap, double pdj, double pjpe) {
  ResultReport r;
  r.results_path = "r.json";
  EvalSummary summary;
  summary.stats = {{"AP", ap}, {"APm", -1.0}};
  r.keypoints = summary;
  r.keypoint_metrics = metrics(pdj, pjpe);
  return r;
}

TEST(EvalReportTest, PercentChange) {
  EXPECT_DOUBLE_EQ(*percent_change(0.75, 0.5), 50.0);
  EXPECT_DOUBLE_EQ(*percent_change(2.0, 4.0), -50.0);
  EXPECT_FALSE(percent_change(1.0, 0.0).has_value());
  EXPECT_FALSE(percent_change(std::nullopt, 1.0).has_value());
}

TEST(EvalReportTest, MetricsJsonHasBothRunsAndChange) {
  const ResultReport ours = report(0.6, 0.9, 5.0), base = report(0.5, 0.75, 10.0);
  const auto j = metrics_json("gt.json", "coco17", ours, &base);
  EXPECT_DOUBLE_EQ(j["results"]["keypoints"]["stats"]["AP"].get<double>(), 0.6);
  EXPECT_DOUBLE_EQ(j["baseline"]["keypoint_metrics"]["keypoints"]["nose"]["pjpe"].get<double>(),
                   10.0);
  EXPECT_NEAR(j["change_percent"]["keypoints"]["AP"].get<double>(), 20.0, 1e-12);
  EXPECT_TRUE(j["change_percent"]["keypoints"]["APm"].is_null());  // -1: undefined
  EXPECT_DOUBLE_EQ(
      j["change_percent"]["keypoint_metrics"]["keypoints"]["nose"]["pjpe"].get<double>(), -50.0);
  EXPECT_FALSE(metrics_json("gt.json", "coco17", ours, nullptr).contains("baseline"));
}

TEST(EvalReportTest, MarkdownRowsLikeThePaper) {
  const ResultReport ours = report(0.6, 0.9, 5.0), base = report(0.5, 0.75, 10.0);
  const std::string md = comparison_markdown(ours, base);
  EXPECT_NE(md.find("| KP AP | 0.500 | 0.600 | +20.00% |"), std::string::npos) << md;
  EXPECT_NE(md.find("| KP APm | n/a | n/a | n/a |"), std::string::npos) << md;
  EXPECT_NE(
      md.find("| nose | 0.900 (+20.00%) | 5.00 (-50.00%) | 0.500 (+0.00%) | 0.250 (+0.00%) |"),
      std::string::npos)
      << md;
  EXPECT_NE(keypoint_table_markdown(*ours.keypoint_metrics)
                .find("| nose | 0.900 | 5.00 | 0.500 | 0.250 | 4 | 1 |"),
            std::string::npos);
}

TEST(EvalVizTest, EvenlySpacedPicks) {
  EXPECT_EQ(evenly_spaced(10, 3), (std::vector<int>{0, 3, 6}));
  EXPECT_EQ(evenly_spaced(2, 5), (std::vector<int>{0, 1}));
  EXPECT_TRUE(evenly_spaced(4, 0).empty());
}

// Image 1: one person found exactly (1.0). Image 2: one exact, one missed (0.5). Image 3: a
// person the only detection misses by far (~0). Image 4: no people (no score, never ranked).
TEST(EvalVizTest, ImagesRankedByHowWellTheirPeopleAreFound) {
  using namespace coco::fixtures;
  const coco::CocoGroundTruth gt = coco::parse_coco_gt(
      gt_file({1, 2, 3, 4}, {gt_person(1, 1, 10, 10, 3200), gt_person(2, 2, 10, 10, 3200),
                             gt_person(3, 2, 200, 10, 3200), gt_person(4, 3, 10, 10, 3200)}),
      "gt", 17, true);
  const coco::CocoResults results =
      coco::parse_coco_results(json_list({kp_result(1, 10, 10, 0.9), kp_result(2, 10, 10, 0.9),
                                          kp_result(3, 300, 300, 0.9), kp_result(4, 10, 10, 0.9)}),
                               "dt", gt, 17);
  const std::vector<double> scores =
      image_pose_scores(gt, results, load_keypoint_template("coco17"));
  ASSERT_EQ(scores.size(), 4u);
  EXPECT_DOUBLE_EQ(scores[0], 1.0);
  EXPECT_DOUBLE_EQ(scores[1], 0.5);
  EXPECT_LT(scores[2], 1e-6);
  EXPECT_TRUE(std::isnan(scores[3]));
  EXPECT_EQ(ranked_positions(scores, 2, VizPick::kBest), (std::vector<int>{0, 1}));
  EXPECT_EQ(ranked_positions(scores, 5, VizPick::kWorst), (std::vector<int>{2, 1, 0}));
  EXPECT_TRUE(ranked_positions(scores, 0, VizPick::kBest).empty());
}

}  // namespace
}  // namespace wheelpose::eval
