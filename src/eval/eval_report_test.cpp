#include "eval/eval_report.h"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace wheelpose::eval
