#include "experiment/spec.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

#include "core/error.h"
#include "experiment/experiment_test_support.h"

namespace wheelpose::experiment {
namespace {

using ::testing::HasSubstr;
using testing::kSmallExperiment;
using testing::scratch_dir;
using testing::test_commands;

std::vector<Variant> parse(const std::string& text, const std::filesystem::path& dir) {
  return parse_experiment(text, "exp.yaml", dir, test_commands());
}

// The error message parsing `text` gives (empty when it parses).
std::string error_of(const std::string& text, const std::filesystem::path& dir) {
  try {
    parse(text, dir);
  } catch (const Error& e) {
    EXPECT_EQ(e.exit_code(), 2);
    return e.what();
  }
  return "";
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

TEST(ExperimentSpec, ParsesTheBaseAndEveryVariant) {
  const auto dir = scratch_dir("parse");
  const auto variants = parse(kSmallExperiment, dir);
  ASSERT_EQ(variants.size(), 3u);
  EXPECT_EQ(variants[0].name, "base");
  EXPECT_EQ(variants[1].name, "real-only");
  EXPECT_EQ(variants[2].name, "distilled");
  const ExperimentSpec& base = variants[0].spec;
  ASSERT_EQ(base.datasets.size(), 4u);
  EXPECT_EQ(base.datasets[0].kind, DatasetSpec::Kind::kGenerate);
  EXPECT_EQ(*base.datasets[0].generate_config, dir / "scene.yaml");  // relative to the file
  EXPECT_EQ(base.datasets[3].part, 1);
  ASSERT_EQ(base.training->sets.size(), 2u);
  EXPECT_DOUBLE_EQ(base.training->sets[1].weight, 3);
  EXPECT_EQ(base.training->options.size(), 2u);
  EXPECT_EQ(base.models[2].blend, 0.5);
  EXPECT_EQ(base.scores[0].size, 256);
  EXPECT_EQ(base.scores[1].type, "both");
  // Each variant is the base with its keys written over it, nothing else.
  ASSERT_EQ(variants[1].spec.training->sets.size(), 1u);
  EXPECT_EQ(variants[1].spec.training->sets[0].set, "real-train");
  EXPECT_EQ(variants[1].spec.training->options, base.training->options);
  ASSERT_EQ(variants[2].spec.training->options.size(), 3u);
  EXPECT_EQ(variants[2].spec.training->options[2],
            std::make_pair(std::string("distill"), std::string("0.1")));
  EXPECT_EQ(variants[2].spec.training->sets.size(), 2u);
}

TEST(ExperimentSpec, BadFilesNameTheFileLineAndKey) {
  const auto dir = scratch_dir("errors");
  const std::string text = kSmallExperiment;
  // An unknown key, at any depth, and one a variant writes.
  EXPECT_THAT(error_of(replaced(text, "options: {steps", "optionz: {steps"), dir),
              HasSubstr("exp.yaml:11: key 'training.optionz': unknown key"));
  EXPECT_THAT(error_of(replaced(text, "frames: 8", "frame: 8"), dir),
              HasSubstr("key 'datasets.renders.generate.frame': unknown key"));
  EXPECT_THAT(error_of(replaced(text, "training.options.distill", "training.option.distill"), dir),
              HasSubstr("key 'training.option': unknown key"));
  // Options train does not have, or that the experiment sets itself.
  EXPECT_THAT(error_of(replaced(text, "batch: 4", "batchsize: 4"), dir),
              HasSubstr("key 'training.options.batchsize': not an option of `wheelpose train`"));
  EXPECT_THAT(error_of(replaced(text, "batch: 4", "out: x"), dir),
              HasSubstr("set by the experiment itself"));
  // Paths, names and values.
  EXPECT_THAT(
      error_of(replaced(text, "coco: real.json", "coco: nowhere.json"), dir),
      HasSubstr("key 'datasets.real.coco': " + (dir / "nowhere.json").string() + ": no such file"));
  EXPECT_THAT(error_of(replaced(text, "images: photos", "images: real.json"), dir),
              HasSubstr("no such folder"));
  EXPECT_THAT(
      error_of(replaced(text, "{set: real-train, weight: 3}", "{set: reel, weight: 3}"), dir),
      HasSubstr("exp.yaml: no dataset named 'reel'"));
  EXPECT_THAT(error_of(replaced(text, "weight: 3", "weight: 0"), dir), HasSubstr("outside"));
  EXPECT_THAT(error_of(replaced(text, "models: [tuned]", "models: [tunde]"), dir),
              HasSubstr("no model named 'tunde'"));
  EXPECT_THAT(error_of(replaced(text, "size: 256", "size: 250"), dir), HasSubstr("steps of 32"));
  EXPECT_THAT(error_of(replaced(text, "type: bbox", "type: boxes"), dir),
              HasSubstr("'boxes' is not one of"));
  EXPECT_THAT(error_of(replaced(text, "start: model.json", "start: missing.json"), dir),
              HasSubstr("key 'models.start'"));
  EXPECT_THAT(error_of(replaced(text, "of: real,", "of: real-val,"), dir),
              HasSubstr("not a generate: or coco: dataset"));
  EXPECT_THAT(error_of(replaced(text, "val: real-val", "keep: best"), dir),
              HasSubstr("key 'training.keep': best needs a val: set"));
  EXPECT_THAT(error_of("name: x\ndatasets: [oops", dir), HasSubstr("YAML syntax error"));
  EXPECT_THAT(
      error_of(replaced(text, "start: model.json", "start: {members: model.json, export: true}"),
               dir),
      HasSubstr("key 'models.start': export: applies to a 'trained' member"));
  EXPECT_THAT(error_of(replaced(text, "blend: 0.5}", "blend: 0.5, export: yes please}"), dir),
              HasSubstr("key 'models.half.export'"));
  // intervals: a model of the file, a count of resamples in range, no other keys.
  EXPECT_THAT(error_of(text + "intervals: {against: nobody}\n", dir),
              HasSubstr("exp.yaml:22: key 'intervals.against': no model named 'nobody'"));
  EXPECT_THAT(error_of(text + "intervals: {against: start, resamples: 0}\n", dir),
              HasSubstr("key 'intervals.resamples'"));
  EXPECT_THAT(error_of(text + "intervals: {against: start, sed: 1}\n", dir),
              HasSubstr("key 'intervals.sed': unknown key"));
  EXPECT_EQ(error_of(text, dir), "");
}

TEST(ExperimentSpec, AFileThatCannotBeReadIsOneError) {
  const auto dir = scratch_dir("file");
  try {
    load_experiment(dir / "none.yaml", test_commands());
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_THAT(e.what(), HasSubstr("none.yaml: cannot open experiment file"));
  }
  EXPECT_THROW(load_experiment(dir, test_commands()), Error);  // a folder
}

}  // namespace
}  // namespace wheelpose::experiment
