#include "experiment/plan.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <string>

#include "experiment/experiment_test_support.h"

namespace wheelpose::experiment {
namespace {

using ::testing::ElementsAre;
using testing::kSmallExperiment;
using testing::scratch_dir;
using testing::test_commands;

std::vector<std::string> ids_of(const Plan& plan, const std::string& kind) {
  std::vector<std::string> ids;
  for (const Step& s : plan.steps) {
    if (s.kind == kind) ids.push_back(s.id);
  }
  return ids;
}

// The plan of `text`'s base variant alone, in a scratch folder named by `tag`.
Plan base_plan(const std::string& text, const std::string& tag) {
  const auto dir = scratch_dir(tag);
  return make_plan({parse_experiment(text, "exp.yaml", dir, test_commands())[0]}, dir / "run");
}

// `text` with the first `from` replaced by `to`.
std::string replaced(std::string text, const std::string& from, const std::string& to) {
  return text.replace(text.find(from), from.size(), to);
}

TEST(ExperimentPlan, VariantsShareWhatTheyHaveInCommon) {
  const auto dir = scratch_dir("plan");
  const auto variants = parse_experiment(kSmallExperiment, "exp.yaml", dir, test_commands());
  const Plan plan = make_plan(variants, dir / "run");
  // One generation and one split for all three variants; a training each.
  EXPECT_EQ(ids_of(plan, "generate").size(), 1u);
  EXPECT_EQ(ids_of(plan, "split").size(), 1u);
  EXPECT_EQ(ids_of(plan, "train").size(), 3u);
  EXPECT_EQ(ids_of(plan, "blend").size(), 3u);
  // The untrained start scores once; the trained models per variant: 1 + 3 × 2 on the real
  // set, 3 on the renders (only `tuned`).
  EXPECT_EQ(ids_of(plan, "score").size(), 1u + 6u + 3u);
  EXPECT_EQ(plan.scores.size(), 3u * 3u + 3u);
  // Steps come after the steps whose output they read.
  const auto index = [&](const std::string& kind) {
    return std::find_if(plan.steps.begin(), plan.steps.end(),
                        [&](const Step& s) { return s.kind == kind; }) -
           plan.steps.begin();
  };
  EXPECT_LT(index("split"), index("train"));
  EXPECT_LT(index("train"), index("blend"));
}

TEST(ExperimentPlan, CommandsAreWhatTheFileSays) {
  const auto dir = scratch_dir("commands");
  const auto variants = parse_experiment(kSmallExperiment, "exp.yaml", dir, test_commands());
  const Plan plan = make_plan({variants[0]}, dir / "run");
  const auto step = [&](const std::string& kind) {
    return *std::find_if(plan.steps.begin(), plan.steps.end(),
                         [&](const Step& s) { return s.kind == kind; });
  };
  const Step generate = step("generate");
  EXPECT_THAT(generate.commands[0],
              ElementsAre("generate", "--out", generate.dir.string(), "--frames", "8", "--seed",
                          "5", "--config", (dir / "scene.yaml").string()));
  EXPECT_TRUE(generate.resumable);
  const Step split = step("split");
  EXPECT_THAT(split.commands[0],
              ElementsAre("coco", "split", (dir / "real.json").string(), "--ratios", "3,1",
                          "--names", "part0,part1", "--group-by", "image", "--seed", "0", "--out",
                          split.dir.string()));
  EXPECT_EQ(split.link_images, dir / "photos");
  const Step train = step("train");
  EXPECT_THAT(train.commands[0],
              ElementsAre("train", "--train", (generate.dir / "annotations.json").string(),
                          "--train", (split.dir / "part0.json").string() + ":3", "--val",
                          (split.dir / "part1.json").string(), "--steps", "20", "--batch", "4",
                          "--out", train.dir.string()));
  const Step blend = step("blend");
  EXPECT_THAT(blend.commands[0],
              ElementsAre("model", "blend", "--start", "movenet-multipose", "--finetuned",
                          (train.dir / "best.pt").string(), "--alpha", "0.5", "--out",
                          (blend.dir / "blend.pt").string()));
  const Step score = step("score");
  ASSERT_EQ(score.commands.size(), 2u);
  EXPECT_THAT(score.commands[0],
              ElementsAre("predict", "--model", (dir / "model.json").string(), "--coco",
                          (dir / "real.json").string(), "--images", (dir / "photos").string(),
                          "--size", "256", "--out", (score.dir / "results.json").string()));
  EXPECT_THAT(score.commands[1], ElementsAre("eval", "--gt", (dir / "real.json").string(), "--dt",
                                             (score.dir / "results.json").string(), "--type",
                                             "bbox", "--out", score.dir.string()));
}

// intervals: every score but the baseline's own points at the baseline's results on the same
// set; a set the baseline is not scored on gets none.
TEST(ExperimentPlan, IntervalsPairEachScoreWithTheBaselineOnItsSet) {
  const auto dir = scratch_dir("intervals");
  const std::string text = std::string(kSmallExperiment) + "intervals: {against: start, seed: 4}\n";
  const Plan plan =
      make_plan({parse_experiment(text, "exp.yaml", dir, test_commands())[0]}, dir / "run");
  const ScoreRef* start = nullptr;
  for (const ScoreRef& s : plan.scores) {
    if (s.model == "start") start = &s;
  }
  ASSERT_NE(start, nullptr);
  EXPECT_TRUE(start->baseline_results.empty());
  EXPECT_EQ(start->gt, dir / "real.json");
  int paired = 0;
  for (const ScoreRef& s : plan.scores) {
    if (s.model == "start") continue;
    if (s.set == "real") {
      ++paired;
      EXPECT_EQ(s.baseline_results, start->results);
      EXPECT_EQ(s.baseline_model, "start");
      EXPECT_EQ(s.resamples, 1000);
      EXPECT_EQ(s.resample_seed, 4u);
      EXPECT_EQ(s.results, s.metrics.parent_path() / "results.json");
    } else {
      EXPECT_TRUE(s.baseline_results.empty()) << s.set;  // only `tuned` is scored there
    }
  }
  EXPECT_EQ(paired, 2);
}

// A blend's label shows the alpha as written; its command keeps every digit, so the weights are
// exactly the file's and the steps of runs made before keep their hashes.
TEST(ExperimentPlan, ABlendIsLabelledByItsAlphaAsWritten) {
  const Plan plan = base_plan(replaced(kSmallExperiment, "blend: 0.5", "blend: 0.3"), "alpha");
  const auto blend = std::find_if(plan.steps.begin(), plan.steps.end(),
                                  [](const Step& s) { return s.kind == "blend"; });
  ASSERT_NE(blend, plan.steps.end());
  EXPECT_EQ(blend->label.substr(blend->label.rfind(' ') + 1), "0.3");
  const auto& command = blend->commands[0];
  const auto alpha = std::find(command.begin(), command.end(), "--alpha");
  ASSERT_NE(alpha, command.end());
  EXPECT_EQ(alpha[1], "0.29999999999999999");
  EXPECT_EQ(std::stod(alpha[1]), 0.3);
}

TEST(ExperimentPlan, StepsAreNamedByWhatTheyDoNotWhereTheRunLives) {
  const auto dir = scratch_dir("names");
  const auto variants = parse_experiment(kSmallExperiment, "exp.yaml", dir, test_commands());
  const Plan a = make_plan(variants, dir / "run-a");
  const Plan b = make_plan(variants, dir / "elsewhere" / "run-b");
  ASSERT_EQ(a.steps.size(), b.steps.size());
  for (std::size_t i = 0; i < a.steps.size(); ++i) EXPECT_EQ(a.steps[i].id, b.steps[i].id);
  // A changed setting is a new step, never a reused one.
  const std::string more =
      std::string(kSmallExperiment)
          .replace(std::string(kSmallExperiment).find("steps: 20"), 9, "steps: 21");
  const Plan c = make_plan(parse_experiment(more, "exp.yaml", dir, test_commands()), dir / "run-a");
  EXPECT_EQ(ids_of(a, "generate"), ids_of(c, "generate"));
  EXPECT_NE(ids_of(a, "train"), ids_of(c, "train"));
  EXPECT_EQ(stable_hash("wheelpose"), "35192a84071ac219");  // FNV-1a 64, never a per-run hash
}

// Editing a file the experiment reads (here the scenario) makes new steps from the first one
// that reads it on: a resumed run never reuses frames rendered from the old file.
TEST(ExperimentPlan, AnEditedInputFileIsANewStep) {
  const auto dir = scratch_dir("edited");
  const auto variants = parse_experiment(kSmallExperiment, "exp.yaml", dir, test_commands());
  const Plan before = make_plan(variants, dir / "run");
  EXPECT_EQ(ids_of(make_plan(variants, dir / "run"), "generate"), ids_of(before, "generate"));
  std::ofstream(dir / "scene.yaml") << "image: {width: 96}\n";
  const Plan after = make_plan(variants, dir / "run");
  EXPECT_NE(ids_of(after, "generate"), ids_of(before, "generate"));
  EXPECT_NE(ids_of(after, "train"), ids_of(before, "train"));
  EXPECT_EQ(ids_of(after, "split"), ids_of(before, "split"));  // it never reads the scenario
  // The same for annotations: every step reading real.json changes, the generation does not.
  std::ofstream(dir / "real.json") << "{\"images\": []}";
  const Plan relabelled = make_plan(variants, dir / "run");
  EXPECT_EQ(ids_of(relabelled, "generate"), ids_of(after, "generate"));
  EXPECT_NE(ids_of(relabelled, "split"), ids_of(after, "split"));
}

// export: the trained (or blended) weights are scored as `model export` writes them, the form a
// model ships in; the export step follows the blend it reads.
TEST(ExperimentPlan, AnExportedModelIsScoredFromItsExport) {
  const Plan plan =
      base_plan(replaced(kSmallExperiment, "blend: 0.5}", "blend: 0.5, export: true}"), "export");
  const auto find = [&](const std::string& kind) {
    return std::find_if(plan.steps.begin(), plan.steps.end(),
                        [&](const Step& s) { return s.kind == kind; });
  };
  const auto blend = find("blend"), exported = find("export");
  ASSERT_NE(exported, plan.steps.end());
  EXPECT_LT(blend, exported);
  EXPECT_EQ(exported->label, "export blend base 0.5");
  EXPECT_THAT(exported->commands[0],
              ElementsAre("model", "export", (blend->dir / "blend.pt").string(), "--out",
                          (exported->dir / "model").string()));
  int from_export = 0;
  for (const Step& s : plan.steps) {
    if (s.kind != "score" || s.label.find("score half ") != 0) continue;
    const auto& predict = s.commands[0];
    const auto model = std::find(predict.begin(), predict.end(), "--model");
    ASSERT_NE(model, predict.end());
    EXPECT_EQ(model[1], (exported->dir / "model" / "model.json").string());
    ++from_export;
  }
  EXPECT_EQ(from_export, 1);
  // The other trained model is scored from its weights as before.
  EXPECT_EQ(std::count_if(plan.steps.begin(), plan.steps.end(),
                          [](const Step& s) { return s.kind == "export"; }),
            1);
}

}  // namespace
}  // namespace wheelpose::experiment
