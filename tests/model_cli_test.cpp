// End-to-end tests of `wheelpose model`: an export that `predict` reads back with the same
// results, a blend, and bad input that leaves nothing behind.

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
using wheelpose::testing::run_wheelpose;
namespace fs = std::filesystem;

bool have_models() {
  return fs::exists(fs::path(WHEELPOSE_SOURCE_DIR) / "models" / "movenet-multipose.json");
}

std::string predict_args(const fs::path& gt, const std::string& model, const fs::path& out) {
  return "predict --model " + model + " --coco " + gt.string() + " --images " +
         wheelpose::testing::coco_sample_dir().string() + " --out " + out.string();
}

TEST(ModelCli, AnExportPredictsLikeItsSourceAndReExportsToTheSameBytes) {
  if (!have_models()) GTEST_SKIP() << "MoveNet models missing: run scripts/setup.sh";
  const auto dir = fresh_temp_dir("model_export");
  const fs::path gt = wheelpose::testing::write_coco_sample_gt(dir, false);
  // A blend is a .pt, so the export goes through the fine-tuned path; alpha 0 keeps the
  // pretrained weights, which are float16 already: the export must predict the same.
  auto r = run_wheelpose("model blend --finetuned movenet-multipose --alpha 0 --out " +
                         (dir / "same.pt").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run_wheelpose("model export " + (dir / "same.pt").string() + " --out " +
                    (dir / "a").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("of movenet-multipose as float16"), std::string::npos) << r.output;
  r = run_wheelpose("model export " + (dir / "a" / "model.json").string() + " --out " +
                    (dir / "b").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* file : {"model.json", "group1-shard1of1.bin"}) {
    EXPECT_EQ(read_text(dir / "a" / file), read_text(dir / "b" / file)) << file;
  }
  ASSERT_EQ(run_wheelpose(predict_args(gt, "movenet-multipose", dir / "pretrained.json")).exit_code,
            0);
  r = run_wheelpose(predict_args(gt, (dir / "a" / "model.json").string(), dir / "export.json"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json pretrained = json::parse(read_text(dir / "pretrained.json"));
  ASSERT_GE(pretrained.size(), 1u);
  EXPECT_EQ(json::parse(read_text(dir / "export.json")), pretrained);
}

// The committed model: found by name, small enough to ship, with its card, and it finds the
// sample's skier (a person without a wheelchair) as well as the pretrained model does at 256.
// The committed models: found by name, small enough to ship, with their cards, and they find the
// sample's skier (a person without a wheelchair) as well as the pretrained model does at 256:
// the blend alone, and the unblended model in the ensemble with the pretrained one.
TEST(ModelCli, TheShippedModelsRunByName) {
  if (!have_models()) GTEST_SKIP() << "MoveNet models missing: run scripts/setup.sh";
  const auto dir = fresh_temp_dir("model_shipped");
  const fs::path gt = wheelpose::testing::write_coco_sample_gt(dir, false);
  for (const std::string name : {"movenet-wheelchair", "movenet-wheelchair-full"}) {
    const fs::path shipped = fs::path(WHEELPOSE_SOURCE_DIR) / "share" / "models" / name;
    ASSERT_TRUE(fs::exists(shipped / "MODEL_CARD.md")) << name;
    EXPECT_LE(
        fs::file_size(shipped / "model.json") + fs::file_size(shipped / "group1-shard1of1.bin"),
        10u * 1000 * 1000);
    const json topology = json::parse(read_text(shipped / "model.json"));
    EXPECT_EQ(topology["userDefinedMetadata"]["wheelpose"]["base_model"], "movenet-multipose");
    const fs::path out = dir / (name + ".json");
    const std::string model =
        name == "movenet-wheelchair" ? name : "movenet-multipose --model " + name + " --flip";
    auto r = run_wheelpose(predict_args(gt, model, out) + " --size 256");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    r = run_wheelpose("eval --gt " + gt.string() + " --dt " + out.string() + " --type keypoints");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_GE(wheelpose::testing::printed_ap(r.output), 0.7) << name << "\n" << r.output;
  }
}

TEST(ModelCli, BadInputGetsOneLineAndNoFiles) {
  if (!have_models()) GTEST_SKIP() << "MoveNet models missing: run scripts/setup.sh";
  const auto dir = fresh_temp_dir("model_bad");
  std::ofstream(dir / "truncated.pt") << "\x80\x02}q";
  auto r = run_wheelpose("model export " + (dir / "truncated.pt").string() + " --out " +
                         (dir / "out").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("truncated.pt: not a weights file"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "out"));
  // The trainer's checkpoint is not a weights file either.
  std::ofstream(dir / "checkpoint.pt") << "PK\x03\x04 not a pickle";
  r = run_wheelpose("model blend --finetuned " + (dir / "checkpoint.pt").string() + " --out " +
                    (dir / "b.pt").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_FALSE(fs::exists(dir / "b.pt"));
  std::ofstream(dir / "file") << "x";
  r = run_wheelpose("model export movenet-multipose --out " + (dir / "file" / "sub").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("file/sub"), std::string::npos) << r.output;
  r = run_wheelpose("model blend --finetuned movenet-multipose --alpha 2 --out " +
                    (dir / "b.pt").string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_FALSE(fs::exists(dir / "b.pt"));
}

}  // namespace
