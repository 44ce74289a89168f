// End-to-end tests of `wheelpose predict`: a pretrained MoveNet on the COCO sample image, scored
// by `wheelpose eval`, and bad input that leaves no results file behind.

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <thread>

#include "cli_runner.h"

namespace {

using nlohmann::json;
using wheelpose::testing::fresh_temp_dir;
using wheelpose::testing::read_text;
using wheelpose::testing::run_wheelpose;
namespace fs = std::filesystem;

fs::path sample_dir() { return wheelpose::testing::coco_sample_dir(); }

bool have_models() {
  return fs::exists(fs::path(WHEELPOSE_SOURCE_DIR) / "models" / "movenet-multipose.json");
}

// `predict` on the sample's image with `args`, into `dir`/`name` (returned).
fs::path predict_sample(const fs::path& dir, const fs::path& gt, const std::string& args,
                        const std::string& name) {
  const fs::path out = dir / name;
  const auto r = run_wheelpose("predict --coco " + gt.string() + " --images " +
                               sample_dir().string() + " --out " + out.string() + args);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  return out;
}

TEST(PredictCli, EveryModelFindsTheSkierAndEvalScoresIt) {
  if (!have_models()) GTEST_SKIP() << "MoveNet models missing: run scripts/setup.sh";
  const auto dir = fresh_temp_dir("predict_models");
  const fs::path gt = wheelpose::testing::write_coco_sample_gt(dir, false);
  for (const std::string model : {"movenet-multipose", "movenet-thunder", "movenet-lightning"}) {
    const fs::path out = dir / (model + ".json");
    auto r = run_wheelpose("predict --model " + model + " --coco " + gt.string() + " --images " +
                           sample_dir().string() + " --out " + out.string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const json results = json::parse(read_text(out));
    ASSERT_GE(results.size(), 1u) << model;
    EXPECT_EQ(results[0]["keypoints"].size(), 51u);
    EXPECT_EQ(results[0]["bbox"].size(), 4u);
    r = run_wheelpose("eval --gt " + gt.string() + " --dt " + out.string() + " --type both");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    // The skier is large and clear: every model gets keypoint AP of at least 0.8.
    EXPECT_GE(wheelpose::testing::printed_ap(r.output), 0.8) << model << "\n" << r.output;
  }
}

TEST(PredictCli, AFolderWithoutACocoFileWorksForMultipose) {
  if (!have_models()) GTEST_SKIP() << "MoveNet models missing: run scripts/setup.sh";
  const auto dir = fresh_temp_dir("predict_folder");
  fs::create_directories(dir / "images");
  fs::copy_file(sample_dir() / "000000000785.jpg", dir / "images" / "a.jpg");
  const auto r = run_wheelpose("predict --images " + (dir / "images").string() + " --out " +
                               (dir / "out.json").string() + " --size 256");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json results = json::parse(read_text(dir / "out.json"));
  ASSERT_GE(results.size(), 1u);
  EXPECT_EQ(results[0]["image_id"], 1);

  // A FIFO as --out (as a pipe or /dev/stdout would be) is written through, never replaced.
  const fs::path fifo = dir / "results.fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::string piped;
  std::thread reader([&] { piped = read_text(fifo); });
  const auto p = run_wheelpose("predict --images " + (dir / "images").string() + " --out " +
                               fifo.string() + " --size 256");
  reader.join();
  EXPECT_EQ(p.exit_code, 0) << p.output;
  EXPECT_TRUE(fs::is_fifo(fifo));
  EXPECT_EQ(json::parse(piped), results);
}

TEST(PredictCli, TheDefaultMergesTheSmallAndTheLargeInput) {
  if (!have_models()) GTEST_SKIP() << "MoveNet models missing: run scripts/setup.sh";
  const auto dir = fresh_temp_dir("predict_scales");
  const fs::path gt = wheelpose::testing::write_coco_sample_gt(dir, false);
  auto run = [&](const std::string& size_args, const std::string& name) {
    return json::parse(read_text(predict_sample(dir, gt, size_args, name)));
  };
  const json small = run(" --size 256", "256.json"), large = run(" --size 640", "640.json");
  const json merged = run("", "default.json");
  EXPECT_EQ(merged, run(" --size 640,256", "reordered.json"));
  // Every merged person is one of a single size's people, unchanged, and none is repeated.
  ASSERT_GE(merged.size(), 1u);
  std::set<std::string> seen;
  for (const json& person : merged) {
    const bool from_one = std::find(small.begin(), small.end(), person) != small.end() ||
                          std::find(large.begin(), large.end(), person) != large.end();
    EXPECT_TRUE(from_one) << person.dump();
    EXPECT_TRUE(seen.insert(person.dump()).second);
  }
  EXPECT_LE(merged.size(), small.size() + large.size());
  const auto r = run_wheelpose("predict --images " + sample_dir().string() + " --out " +
                               (dir / "x.json").string() + " --size 256,256");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("different sizes"), std::string::npos) << r.output;
}

TEST(PredictCli, AnEnsembleFusesItsModelsAndTheFlipItsViews) {
  if (!have_models()) GTEST_SKIP() << "MoveNet models missing: run scripts/setup.sh";
  const auto dir = fresh_temp_dir("predict_ensemble");
  const fs::path gt = wheelpose::testing::write_coco_sample_gt(dir, false);
  auto run = [&](const std::string& args, const std::string& name) {
    return predict_sample(dir, gt, " --size 256" + args, name);
  };
  // A model in an ensemble with itself is that model: every person pairs with its twin.
  const json one = json::parse(read_text(run("", "one.json")));
  const json twice = json::parse(
      read_text(run(" --model movenet-multipose --model movenet-multipose", "twice.json")));
  ASSERT_EQ(one.size(), twice.size());
  for (std::size_t i = 0; i < one.size(); ++i) {
    EXPECT_NEAR(one[i]["score"].get<double>(), twice[i]["score"].get<double>(), 1e-4) << i;
    for (int k = 0; k < 4; ++k)
      EXPECT_NEAR(one[i]["bbox"][k].get<double>(), twice[i]["bbox"][k].get<double>(), 0.011);
    for (int k = 0; k < 51; ++k)
      EXPECT_NEAR(one[i]["keypoints"][k].get<double>(), twice[i]["keypoints"][k].get<double>(),
                  0.011);
  }
  // The mirrored view moves the results, and the skier is still found as well.
  const fs::path flipped = run(" --flip", "flip.json");
  EXPECT_NE(json::parse(read_text(flipped)), one);
  const auto r =
      run_wheelpose("eval --gt " + gt.string() + " --dt " + flipped.string() + " --type keypoints");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_GE(wheelpose::testing::printed_ap(r.output), 0.8) << r.output;
}

TEST(PredictCli, BadInputGivesOneLineAndNoResultsFile) {
  if (!have_models()) GTEST_SKIP() << "MoveNet models missing: run scripts/setup.sh";
  const auto dir = fresh_temp_dir("predict_bad");
  fs::create_directories(dir / "empty");
  fs::create_directories(dir / "broken");
  std::ofstream(dir / "broken" / "x.jpg") << "not a jpeg";
  const fs::path out = dir / "out.json";
  fs::create_directories(dir / "cut");
  const std::string jpeg = read_text(sample_dir() / "000000000785.jpg");
  std::ofstream(dir / "cut" / "a.jpg", std::ios::binary) << jpeg.substr(0, 3000);
  std::ofstream(dir / "empty.json").close();
  const fs::path gt = wheelpose::testing::write_coco_sample_gt(dir, /*copy_image=*/false);
  struct Case {
    std::string args, says;
  } cases[] = {
      {"--images " + (dir / "empty").string(), "no images to predict on"},
      {"--images " + (dir / "cut").string() + " --coco " + (dir / "empty.json").string(),
       "empty.json: empty file, not JSON"},
      {"--images " + (dir / "cut").string() + " --coco " + gt.string(),
       "cut/000000000785.jpg: no such image file"},
      {"--images " + (dir / "cut").string(),
       "cut/a.jpg: truncated JPEG (it ends before its end-of-image marker)"},
      {"--images " + (dir / "cut").string() + " --size 4096",
       "4096 is not a multiple of 32 from 32 to 1280"},
      {"--images " + (dir / "cut").string() + " --size ''",
       "'' is not a whole number (a multiple of 32 from 32 to 1280)"},
      {"--images " + (dir / "cut").string() + " --min-score abc", "'abc' is not a number"},
      {"--images " + (dir / "broken").string(), "x.jpg: cannot decode the image"},
      {"--images " + (dir / "broken").string() + " --size 100",
       "100 is not a multiple of 32 from 32 to 1280"},
      {"--images " + (dir / "broken").string() + " --model movenet-giant", "unknown model"},
      {"--images " + (dir / "broken").string() + " --model movenet-thunder",
       "is a single-person model"},
      {"--images " + (dir / "broken").string() +
           " --model movenet-multipose --model movenet-thunder",
       "--model movenet-thunder: only multipose models make an ensemble"},
      {"--images " + (dir / "broken").string() + " --model movenet-lightning --flip",
       "--flip: movenet-lightning is a single-person model"},
  };
  for (const Case& c : cases) {
    const auto r = run_wheelpose("predict " + c.args + " --out " + out.string());
    EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.says), std::string::npos) << c.args << "\n" << r.output;
    EXPECT_FALSE(fs::exists(out)) << c.args;
    EXPECT_EQ(r.output.find("[ WARN"), std::string::npos) << "OpenCV's own warning: " << r.output;
  }
  // An --out that is a folder: exit 2 naming it, and the folder untouched.
  const auto r = run_wheelpose("predict --images " + (dir / "cut").string() + " --out " +
                               (dir / "empty").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find((dir / "empty").string() + ": is a directory"), std::string::npos)
      << r.output;
  EXPECT_TRUE(fs::is_directory(dir / "empty"));
}

}  // namespace
