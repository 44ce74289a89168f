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

// Damaged model files never give results: a .pt whose bytes changed (its ZIP CRC fails), a
// TF.js shard of random bytes, a folder where a file belongs; and numbers that are not numbers.
TEST(ModelCli, DamagedModelsAndBadNumbersAreRefused) {
  if (!have_models()) GTEST_SKIP() << "MoveNet models missing: run scripts/setup.sh";
  const auto dir = fresh_temp_dir("model_damaged");
  const fs::path gt = wheelpose::testing::write_coco_sample_gt(dir, false);
  auto r = run_wheelpose("model blend --finetuned movenet-multipose --alpha 0 --out " +
                         (dir / "good.pt").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::string bytes = read_text(dir / "good.pt");
  ASSERT_GT(bytes.size(), 1000000u);
  bytes.replace(bytes.size() / 2, 8, "\x7f\xff\xff\xff\x7f\xff\xff\xff", 8);
  std::ofstream(dir / "damaged.pt", std::ios::binary) << bytes;

  fs::create_directories(dir / "folder.pt");
  std::string shard(
      fs::file_size(fs::path(WHEELPOSE_SOURCE_DIR) / "models" / "movenet-multipose.bin"), '\0');
  std::uint32_t state = 12345;
  for (char& c : shard) {
    state = state * 1664525u + 1013904223u;
    c = static_cast<char>(state >> 24);
  }
  fs::copy_file(fs::path(WHEELPOSE_SOURCE_DIR) / "models" / "movenet-multipose.json",
                dir / "movenet-multipose.json");
  std::ofstream(dir / "movenet-multipose.bin", std::ios::binary) << shard;

  struct Case {
    std::string args, says, out;
  } cases[] = {
      {predict_args(gt, (dir / "damaged.pt").string(), dir / "p.json"),
       "damaged.pt: damaged weights file: entry", "p.json"},
      {"model export " + (dir / "damaged.pt").string() + " --out " + (dir / "e").string(),
       "fails its CRC-32 checksum", "e"},
      {"model blend --finetuned " + (dir / "damaged.pt").string() + " --out " +
           (dir / "b.pt").string(),
       "damaged.pt: damaged weights file", "b.pt"},
      {predict_args(gt, (dir / "folder.pt").string(), dir / "p.json"),
       "folder.pt: a folder, not a weights file", "p.json"},
      {predict_args(gt, (dir / "movenet-multipose.json").string(), dir / "p.json"),
       "holds NaN or infinity (a damaged shard?)", "p.json"},
      {"model blend --finetuned movenet-multipose --alpha abc --out " + (dir / "b.pt").string(),
       "'abc' is not a number", "b.pt"},
      {"model blend --finetuned movenet-multipose --alpha 1.5 --out " + (dir / "b.pt").string(),
       "1.5 is outside [0, 1]", "b.pt"},
      {"model blend --finetuned movenet-multipose --alpha-for center_=0.5x --out " +
           (dir / "b.pt").string(),
       "'center_=0.5x' is not PART=ALPHA with ALPHA a number in [0, 1]", "b.pt"},
      {"model blend --finetuned movenet-multipose --out " + dir.string(),
       dir.string() + ": is a directory, not a file to write", ""},
  };
  for (const Case& c : cases) {
    r = run_wheelpose(c.args);
    EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.says), std::string::npos) << c.args << "\n" << r.output;
    EXPECT_LT(r.output.find(c.says), r.output.find('\n')) << "on the first line: " << r.output;
    if (!c.out.empty()) {
      EXPECT_FALSE(fs::exists(dir / c.out)) << c.args;
    }
  }
}

}  // namespace
