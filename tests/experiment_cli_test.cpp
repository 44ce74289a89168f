// End-to-end tests of `wheelpose experiment`: the quick experiment (configs/experiments/
// quick.yaml) runs every stage, survives a kill, resumes to the same results.json, and its
// numbers are those of `predict` + `eval` run by hand; bad files are refused before any work.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_runner.h"

namespace {

using nlohmann::json;
using wheelpose::testing::fresh_temp_dir;
using wheelpose::testing::read_text;
using wheelpose::testing::run_killed_until_done;
using wheelpose::testing::run_wheelpose;
namespace fs = std::filesystem;

const fs::path kQuick = fs::path(WHEELPOSE_SOURCE_DIR) / "configs" / "experiments" / "quick.yaml";

bool models_missing() {
  return !fs::exists(fs::path(WHEELPOSE_SOURCE_DIR) / "models" / "movenet-multipose.json");
}

TEST(ExperimentCli, QuickRunSurvivesAKillAndReportsWhatPredictAndEvalSay) {
  if (models_missing()) GTEST_SKIP() << "MoveNet models missing: run scripts/setup.sh";
  const fs::path dir = fresh_temp_dir("experiment_quick");
  const fs::path out = dir / "run";
  // Killed once mid-run (the generation and training are under way by then), then resumed.
  const auto runs = run_killed_until_done(
      [&] {
        return "-q experiment run " + kQuick.string() + " --out " + out.string() +
               (fs::exists(out / "experiment.yaml") ? " --resume" : "");
      },
      10, 600);
  ASSERT_EQ(runs.failure, "");
  EXPECT_EQ(runs.kills, 1);
  const json results = json::parse(read_text(out / "results.json"));
  EXPECT_EQ(results["experiment"], "quick");
  EXPECT_EQ(results["config"], read_text(kQuick));
  EXPECT_EQ(results["variants"], json({"base", "distill"}));
  // 4 models × 2 variants on the test set, every one with keypoint and box AP.
  ASSERT_EQ(results["results"].size(), 8u);
  for (const json& row : results["results"]) {
    EXPECT_TRUE(row.contains("keypoints") && row.contains("bbox")) << row.dump();
    EXPECT_GE(row["keypoints"]["AP"].get<double>(), 0) << row.dump();
  }
  EXPECT_TRUE(fs::exists(out / "report.md"));
  EXPECT_NE(read_text(out / "report.html").find("<img src=\"steps/train-"), std::string::npos);
  EXPECT_EQ(results["training_curves"].size(), 2u);
  for (const auto& [variant, curves] : results["training_curves"].items()) {
    EXPECT_TRUE(fs::exists(out / curves.get<std::string>())) << variant;
  }

  // The same numbers as a run never interrupted.
  const fs::path whole = dir / "whole";
  const auto uninterrupted =
      run_wheelpose("-q experiment run " + kQuick.string() + " --out " + whole.string());
  ASSERT_EQ(uninterrupted.exit_code, 0) << uninterrupted.output;
  EXPECT_EQ(json::parse(read_text(whole / "results.json"))["results"], results["results"]);

  // Resumed when finished: nothing runs again and results.json keeps its bytes.
  const std::string before = read_text(out / "results.json");
  const auto again =
      run_wheelpose("experiment run " + kQuick.string() + " --out " + out.string() + " --resume");
  ASSERT_EQ(again.exit_code, 0) << again.output;
  EXPECT_NE(again.output.find("done before"), std::string::npos);
  EXPECT_EQ(read_text(out / "results.json"), before);
  // Without --resume a finished run is not overwritten.
  const auto refused =
      run_wheelpose("experiment run " + kQuick.string() + " --out " + out.string());
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_NE(refused.output.find("holds an experiment run"), std::string::npos) << refused.output;

  // The blend was scored from its export (float16 TF.js files), one per variant.
  int exports = 0;
  for (const auto& entry : fs::directory_iterator(out / "steps")) {
    if (!entry.path().filename().string().starts_with("export-")) continue;
    ++exports;
    EXPECT_TRUE(fs::exists(entry.path() / "model" / "model.json"));
    EXPECT_TRUE(fs::exists(entry.path() / "model" / "group1-shard1of1.bin"));
  }
  EXPECT_EQ(exports, 2);

  // Training changed the weights: the fine-tuned rows are not the pretrained one.
  EXPECT_NE(results["results"][0]["keypoints"], results["results"][1]["keypoints"]);
  EXPECT_EQ(results["results"][0]["model"], "pretrained");
  EXPECT_EQ(results["results"][1]["model"], "fine-tuned");

  // The pretrained row is what predict and eval say by hand on the generated test set.
  fs::path test_dir;
  for (const auto& entry : fs::directory_iterator(out / "steps")) {
    if (entry.path().filename().string().starts_with("generate-test-")) test_dir = entry.path();
  }
  ASSERT_FALSE(test_dir.empty());
  const fs::path gt = test_dir / "annotations.json";
  ASSERT_EQ(run_wheelpose("-q predict --coco " + gt.string() + " --images " +
                          (test_dir / "images").string() + " --out " + (dir / "dt.json").string())
                .exit_code,
            0);
  ASSERT_EQ(run_wheelpose("-q eval --type both --gt " + gt.string() + " --dt " +
                          (dir / "dt.json").string() + " --out " + (dir / "eval").string())
                .exit_code,
            0);
  const json by_hand = json::parse(read_text(dir / "eval" / "metrics.json"))["results"];
  bool found = false;
  for (const json& row : results["results"]) {
    if (row["model"] != "pretrained") continue;
    found = true;
    EXPECT_EQ(row["keypoints"], by_hand["keypoints"]["stats"]);
    EXPECT_EQ(row["bbox"], by_hand["bbox"]["stats"]);
  }
  EXPECT_TRUE(found);
}

TEST(ExperimentCli, BadFilesAreRefusedBeforeAnyWork) {
  const fs::path dir = fresh_temp_dir("experiment_bad");
  std::string text = read_text(kQuick);
  const auto write_variant = [&](const std::string& from, const std::string& to) {
    std::string changed = text;
    const auto at = changed.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    changed.replace(at, from.size(), to);
    // Beside quick.yaml's own folder layout, so its relative paths still hold.
    const fs::path file = dir / "experiments" / "bad.yaml";
    fs::create_directories(file.parent_path());
    fs::copy_file(fs::path(WHEELPOSE_SOURCE_DIR) / "configs" / "boost-train.yaml",
                  dir / "boost-train.yaml", fs::copy_options::skip_existing);
    fs::copy_file(fs::path(WHEELPOSE_SOURCE_DIR) / "configs" / "boost-train-clips.json",
                  dir / "boost-train-clips.json", fs::copy_options::skip_existing);
    fs::copy_file(fs::path(WHEELPOSE_SOURCE_DIR) / "configs" / "boost-test-clips.json",
                  dir / "boost-test-clips.json", fs::copy_options::skip_existing);
    std::ofstream(file) << changed;
    return file;
  };
  const struct {
    std::string from, to, message;
  } cases[] = {
      {"input-size: 128", "input-sise: 128",
       "key 'training.options.input-sise': not an option of `wheelpose train`"},
      {"frames: 16", "frame: 16", "key 'datasets.train.generate.frame': unknown key"},
      {"../boost-test-clips.json", "../no-clips.json", "no-clips.json: no such file"},
      {"fine-tuned: trained", "fine-tuned: movenet-nothing", "key 'models.fine-tuned'"},
      {"training.options.distill", "training.option.distill", "key 'training.option': unknown key"},
  };
  for (const auto& c : cases) {
    const fs::path file = write_variant(c.from, c.to);
    const auto result =
        run_wheelpose("experiment run " + file.string() + " --out " + (dir / "run").string());
    EXPECT_EQ(result.exit_code, 2) << c.to << ": " << result.output;
    EXPECT_NE(result.output.find(c.message), std::string::npos) << c.to << ": " << result.output;
    EXPECT_NE(result.output.find("bad.yaml"), std::string::npos) << result.output;
    EXPECT_FALSE(fs::exists(dir / "run")) << "work started for " << c.to;
  }
  const auto missing = run_wheelpose("experiment run " + (dir / "none.yaml").string() + " --out " +
                                     (dir / "run").string());
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.output.find("none.yaml: cannot open experiment file"), std::string::npos);
  // plan prints every step's commands without running them.
  const auto plan =
      run_wheelpose("experiment plan " + kQuick.string() + " --out " + (dir / "run").string());
  ASSERT_EQ(plan.exit_code, 0) << plan.output;
  EXPECT_NE(plan.output.find("wheelpose train --train"), std::string::npos) << plan.output;
  EXPECT_NE(plan.output.find("--distill 0.02"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir / "run"));
}

// Every experiment the docs cite checks out: it plans, or (the real-photo ones, on a machine
// without the locally built real sets) fails only for a missing set under out/.
TEST(ExperimentCli, EveryShippedExperimentFileIsValid) {
  const fs::path folder = fs::path(WHEELPOSE_SOURCE_DIR) / "configs" / "experiments";
  int files = 0;
  for (const auto& entry : fs::directory_iterator(folder)) {
    if (entry.path().extension() != ".yaml") continue;
    ++files;
    const auto plan = run_wheelpose("experiment plan " + entry.path().string());
    if (plan.exit_code == 0) continue;
    EXPECT_EQ(plan.exit_code, 2) << entry.path() << ": " << plan.output;
    EXPECT_TRUE(plan.output.find("/out/") != std::string::npos &&
                (plan.output.find("no such file") != std::string::npos ||
                 plan.output.find("no such folder") != std::string::npos) &&
                plan.output.find("models/") == std::string::npos)
        << entry.path() << ": " << plan.output;
  }
  EXPECT_GE(files, 6);
}

}  // namespace
