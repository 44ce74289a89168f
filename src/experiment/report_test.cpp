#include "experiment/report.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>

#include "core/atomic_file.h"
#include "core/coco_test_fixtures.h"
#include "experiment/experiment_test_support.h"

namespace wheelpose::experiment {
namespace {

using nlohmann::json;
using ::testing::HasSubstr;

void write_metrics(const std::filesystem::path& file, double keypoint_ap, double box_ap) {
  std::filesystem::create_directories(file.parent_path());
  json results = json::object();
  if (keypoint_ap >= 0) results["keypoints"] = {{"stats", {{"AP", keypoint_ap}, {"AP50", 0.9}}}};
  results["bbox"] = {{"stats", {{"AP", box_ap}, {"AP50", -1.0}}}};
  std::ofstream(file) << json{{"results", results}}.dump();
}

TEST(ExperimentReport, TablesHoldEveryScoreByItsSet) {
  const auto dir = testing::scratch_dir("report");
  Plan plan;
  plan.scores = {{"base", "pretrained", "real", "both", 256, dir / "a" / "metrics.json"},
                 {"base", "tuned", "real", "both", 256, dir / "b" / "metrics.json"},
                 {"rehearsal-only", "tuned", "test", "bbox", 0, dir / "c" / "metrics.json"},
                 {"base", "tuned", "test", "bbox", 0, dir / "never-ran" / "metrics.json"}};
  plan.train_runs["base"] = dir / "run" / "steps" / "train-base-0123";
  write_metrics(plan.scores[0].metrics, 0.4567, 0.25);
  write_metrics(plan.scores[1].metrics, 0.5, 0.3049);
  write_metrics(plan.scores[2].metrics, -1, 0.125);
  const ReportInputs inputs{"demo", "A <test> run", "name: demo\n", "abc123", "exp.yaml", {"base"}};
  const json results =
      collect_results(inputs, plan, {{"train-base-0123", "train", "train base", 12.6}});
  ASSERT_EQ(results["results"].size(), 3u);  // the unscored one is left out
  EXPECT_DOUBLE_EQ(results["results"][1]["keypoints"]["AP"].get<double>(), 0.5);
  EXPECT_FALSE(results["results"][2].contains("keypoints"));
  EXPECT_EQ(results["config"], "name: demo\n");
  EXPECT_EQ(results["commit"], "abc123");
  EXPECT_DOUBLE_EQ(results["wall_seconds"].get<double>(), 12.6);
  EXPECT_EQ(results["training_curves"]["base"], "steps/train-base-0123/curves.svg");

  const std::string md = report_markdown(results);
  EXPECT_THAT(md, HasSubstr("## real at --size 256\n"));
  EXPECT_THAT(md, HasSubstr("| base | pretrained | 45.7 | 90.0 | 25.0 | – |\n"));
  EXPECT_THAT(md, HasSubstr("| base | tuned | 50.0 | 90.0 | 30.5 | – |\n"));
  EXPECT_THAT(md, HasSubstr("## test\n"));
  EXPECT_THAT(md, HasSubstr("| rehearsal-only | tuned | – | – | 12.5 | – |\n"));
  EXPECT_THAT(md, HasSubstr("| train base | 13 |"));
  const std::string html = report_html(results);
  EXPECT_THAT(html, HasSubstr("A &lt;test&gt; run"));
  EXPECT_THAT(html, HasSubstr("<img src=\"steps/train-base-0123/curves.svg\""));
  EXPECT_THAT(html, HasSubstr("<td>45.7</td>"));

  write_reports(results, dir);
  EXPECT_EQ(json::parse(read_file(dir / "results.json")), results);
  EXPECT_EQ(read_file(dir / "report.md"), md);
}

// With a baseline the rows carry the paired bootstrap's gain, and the tables show it.
TEST(ExperimentReport, GainsOverTheBaselineComeWithTheirIntervals) {
  namespace fixtures = coco::fixtures;
  const auto dir = testing::scratch_dir("report_gains");
  std::vector<long> images;
  std::vector<json> people, perfect, half;
  for (int i = 1; i <= 12; ++i) {
    images.push_back(i);
    people.push_back(fixtures::gt_person(i, i, 100, 100, 10000));
    perfect.push_back(fixtures::kp_result(i, 100, 100, 0.9));
    // The baseline finds the first half of the people; elsewhere it detects nothing there.
    half.push_back(i <= 6 ? fixtures::kp_result(i, 100, 100, 0.9)
                          : fixtures::kp_result(i, 900, 900, 0.9));
  }
  std::ofstream(dir / "gt.json") << fixtures::gt_file(images, people).dump();
  std::filesystem::create_directories(dir / "a");
  std::filesystem::create_directories(dir / "b");
  std::ofstream(dir / "a" / "results.json") << fixtures::json_list(half).dump();
  std::ofstream(dir / "b" / "results.json") << fixtures::json_list(perfect).dump();
  Plan plan;
  plan.scores = {{"base", "pretrained", "real", "keypoints", 0, dir / "a" / "metrics.json"},
                 {"base", "tuned", "real", "keypoints", 0, dir / "b" / "metrics.json"}};
  for (ScoreRef& s : plan.scores) {
    s.gt = dir / "gt.json";
    s.results = s.metrics.parent_path() / "results.json";
  }
  plan.scores[1].baseline_results = plan.scores[0].results;
  plan.scores[1].baseline_model = "pretrained";
  plan.scores[1].resamples = 200;
  plan.scores[1].resample_seed = 1;
  write_metrics(plan.scores[0].metrics, 0.5, -1);
  write_metrics(plan.scores[1].metrics, 1.0, -1);
  const ReportInputs inputs{"gains", "", "name: gains\n", "abc", "exp.yaml", {"base"}};
  const json results = collect_results(inputs, plan, {});
  EXPECT_FALSE(results["results"][0].contains("against"));
  const json& against = results["results"][1]["against"];
  EXPECT_EQ(against["model"], "pretrained");
  EXPECT_EQ(against["resamples"], 200);
  EXPECT_FALSE(against.contains("bbox"));  // a keypoint score
  const json& ap = against["keypoints"]["AP"];
  // Every person found against the first half found (precision 1 to recall 0.5: 51 of the
  // 101 recall thresholds).
  EXPECT_NEAR(ap["estimate"].get<double>(), 1 - 51.0 / 101, 1e-9);
  EXPECT_GT(ap["low"].get<double>(), 0.0);
  EXPECT_LT(ap["low"].get<double>(), ap["high"].get<double>());
  const std::string md = report_markdown(results);
  EXPECT_THAT(md, HasSubstr("Gains are over `pretrained`"));
  EXPECT_THAT(md, HasSubstr("| keypoint AP gain [95 %] | box AP gain [95 %] |"));
  EXPECT_THAT(md, HasSubstr("| base | pretrained | 50.0 | 90.0 | – | – | – | – |\n"));
  EXPECT_THAT(md, HasSubstr("| base | tuned | 100.0 | 90.0 | – | – | +49.5 ["));
  EXPECT_THAT(report_html(results), HasSubstr("<td>+49.5 ["));
}

}  // namespace
}  // namespace wheelpose::experiment
