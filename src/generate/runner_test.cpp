#include "generate/runner.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>

#include "core/atomic_file.h"
#include "core/config.h"
#include "core/error.h"

namespace wheelpose::generate {
namespace {

TEST(Runner, ShardsPartitionTheFramesInOrder) {
  for (std::int64_t frames : {1, 7, 100, 1001}) {
    for (int count : {1, 2, 3, 8}) {
      std::int64_t next = 0;
      for (int i = 0; i < count; ++i) {
        const auto [first, end] = shard_range(frames, i, count);
        EXPECT_EQ(first, next) << frames << " " << i << "/" << count;
        EXPECT_LE(end - first, frames / count + 1);
        EXPECT_GE(end - first, frames / count);
        next = end;
      }
      EXPECT_EQ(next, frames);
    }
  }
}

// The summary times every stage of a frame; with the threads' times summed, the stages of a
// frame cannot take longer than the threads had.
TEST(Runner, StageTimesArePositiveAndFitTheWallTime) {
  namespace fs = std::filesystem;
  const fs::path assets = fs::path(WHEELPOSE_SHARED_DIR) / "assets";
  if (!fs::exists(assets)) GTEST_SKIP() << "shared assets missing";
  const Scenario scenario = Scenario::from_config(
      ConfigNode::load_string("image: {width: 96, height: 64, spp: 1}\n", "tiny.yaml"));
  RunOptions o;
  o.out = fs::temp_directory_path() / "wheelpose_runner_stages";
  fs::remove_all(o.out);
  o.frames = 3;
  o.seed = 5;
  o.threads = 2;
  o.assets = assets;
  const RunSummary summary = run_generate(scenario, o);
  ASSERT_EQ(summary.rendered, 3);
  const RunSummary::StageMs& ms = summary.stage_ms;
  for (const double stage : {ms.draft, ms.build, ms.bvh, ms.render, ms.label, ms.write}) {
    EXPECT_GT(stage, 0.0);
  }
  const double per_frame_sum = ms.draft + ms.build + ms.bvh + ms.render + ms.label + ms.write;
  EXPECT_LE(per_frame_sum * 3, 2 * 1000 * summary.seconds);
  fs::remove_all(o.out);
}

TEST(Runner, OptionsCheckNamesTheBadOption) {
  RunOptions ok;
  ok.out = "out";
  EXPECT_NO_THROW(ok.check());
  auto message = [](RunOptions o) {
    try {
      o.check();
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  RunOptions o = ok;
  o.frames = 0;
  EXPECT_NE(message(o).find("--frames"), std::string::npos);
  o = ok;
  o.shard_index = 2;
  o.shard_count = 2;
  EXPECT_NE(message(o).find("--shard"), std::string::npos);
  o = ok;
  o.format = "bmp";
  EXPECT_NE(message(o).find("--format"), std::string::npos);
  o = ok;
  o.out.clear();
  EXPECT_NE(message(o).find("--out"), std::string::npos);
  o = ok;
  o.threads = -1;
  EXPECT_NE(message(o).find("--threads"), std::string::npos);
}

// Framing end to end: each framed frame records which camera draw it kept, the output does not
// depend on the thread count, and `attempts: 1` is the unframed run byte for byte.
TEST(Runner, FramingRecordsTheDrawKeptAndStaysDeterministic) {
  namespace fs = std::filesystem;
  const fs::path assets = fs::path(WHEELPOSE_SHARED_DIR) / "assets";
  if (!fs::exists(assets)) GTEST_SKIP() << "shared assets missing";
  auto run = [&](const std::string& yaml, int threads, const std::string& name) {
    RunOptions o;
    o.out = fs::temp_directory_path() / ("wheelpose_runner_framing_" + name);
    fs::remove_all(o.out);
    o.frames = 3;
    o.seed = 7;
    o.threads = threads;
    o.assets = assets;
    run_generate(Scenario::from_config(ConfigNode::load_string(yaml, name + ".yaml")), o);
    std::pair<std::string, std::string> written{read_file(o.out / "annotations.json"), ""};
    for (int f = 0; f < 3; ++f)
      written.second += read_file(o.out / "images" / (frame_stem(f) + ".jpg"));
    fs::remove_all(o.out);
    return written;
  };
  const std::string rooms =
      "image: {width: 96, height: 64, spp: 1}\n"
      "randomizers:\n"
      "  Environment: {room_probability: 1}\n"
      "  HumanGeneration: {min_per_frame: 3, max_per_frame: 4}\n"
      "  Camera: {room_walls: all}\n";
  const std::string framed = rooms + "framing: {attempts: 5, min_visible_share: 0.95}\n";
  const auto one_thread = run(framed, 1, "one");
  EXPECT_TRUE(run(framed, 2, "two") == one_thread);
  const nlohmann::json coco = nlohmann::json::parse(one_thread.first);
  int redrawn = 0;
  for (const auto& image : coco["images"]) {
    ASSERT_TRUE(image.contains("camera_draws"));
    const int draws = image["camera_draws"].get<int>();
    EXPECT_GE(draws, 1);
    EXPECT_LE(draws, 5);
    redrawn += draws > 1;
  }
  EXPECT_GT(redrawn, 0);  // three or four people in a room rarely all show 95 % at once
  const auto unframed = run(rooms, 2, "unframed");
  EXPECT_TRUE(run(rooms + "framing: {attempts: 1}\n", 2, "single") == unframed);
  EXPECT_EQ(unframed.first.find("camera_draws"), std::string::npos);
}

}  // namespace
}  // namespace wheelpose::generate
