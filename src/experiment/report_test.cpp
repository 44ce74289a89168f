#include "experiment/report.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>

#include "core/atomic_file.h"
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

}  // namespace
}  // namespace wheelpose::experiment
