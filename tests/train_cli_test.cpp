// End-to-end tests of `wheelpose train`: a stopped or killed run resumed continues exactly, its
// weights load in `predict`, validation keeps the best weights, two processes train one run,
// and bad input is one line that leaves earlier checkpoints untouched.

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <future>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

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

// Small and single-threaded so the two runs do the same float operations in the same order.
std::string small_run(const fs::path& gt, const fs::path& out) {
  return "train --train " + gt.string() + " --out " + out.string() +
         " --steps 4 --batch 2 --input-size 128 --checkpoint-every 2 --warmup 2 --threads 1 "
         "--seed 3";
}

// Whether two files hold the same bytes. (EXPECT_EQ on two checkpoints' bytes would, on failure,
// make GoogleTest diff megabytes of binary "lines" and exhaust memory; this says where they part.)
::testing::AssertionResult same_bytes(const fs::path& a, const fs::path& b) {
  const std::string x = read_text(a), y = read_text(b);
  if (x == y) return ::testing::AssertionSuccess();
  std::size_t at = 0;
  while (at < x.size() && at < y.size() && x[at] == y[at]) ++at;
  return ::testing::AssertionFailure() << a << " (" << x.size() << " bytes) and " << b << " ("
                                       << y.size() << " bytes) differ from byte " << at;
}

// train_log.csv without the images/s column (wall-clock).
std::string log_without_speed(const fs::path& path) {
  std::istringstream in(read_text(path));
  std::string line, out;
  while (std::getline(in, line)) out += line.substr(0, line.rfind(',')) + "\n";
  return out;
}

TEST(TrainCli, StoppedRunResumesExactlyAndItsWeightsPredict) {
  if (!have_models()) GTEST_SKIP() << "MoveNet models missing: run scripts/setup.sh";
  const auto dir = fresh_temp_dir("train_resume");
  const fs::path gt = wheelpose::testing::write_coco_sample_gt(dir, true);
  auto r = run_wheelpose(small_run(gt, dir / "whole"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run_wheelpose(small_run(gt, dir / "parts") + " --stop-after 1");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(log_without_speed(dir / "parts" / "train_log.csv").find("\n2,"), std::string::npos);
  r = run_wheelpose(small_run(gt, dir / "parts") + " --resume");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(same_bytes(dir / "whole" / "last.pt", dir / "parts" / "last.pt"));
  // The optimizer's state too, in a fixed order (LibTorch's own save writes it in address order).
  EXPECT_TRUE(same_bytes(dir / "whole" / "checkpoint.pt", dir / "parts" / "checkpoint.pt"));
  EXPECT_EQ(log_without_speed(dir / "whole" / "train_log.csv"),
            log_without_speed(dir / "parts" / "train_log.csv"));
  // Four rows and a header, every loss finite.
  const std::string log = log_without_speed(dir / "whole" / "train_log.csv");
  EXPECT_EQ(std::count(log.begin(), log.end(), '\n'), 5);
  EXPECT_EQ(log.find("nan"), std::string::npos) << log;

  r = run_wheelpose("predict --model " + (dir / "whole" / "last.pt").string() + " --coco " +
                    gt.string() + " --images " + dir.string() + " --out " +
                    (dir / "results.json").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(json::parse(read_text(dir / "results.json")).is_array());
}

// kill -9 at growing moments, then a resume (or a fresh start when no checkpoint was written
// yet), until a run completes: the weights and the log equal an uninterrupted run's.
TEST(TrainCli, KilledRunsResumeExactly) {
  if (!have_models()) GTEST_SKIP() << "MoveNet models missing: run scripts/setup.sh";
  const auto dir = fresh_temp_dir("train_kill");
  const fs::path gt = wheelpose::testing::write_coco_sample_gt(dir, true);
  auto run = [&](const fs::path& out) {
    return "train --train " + gt.string() + " --out " + out.string() +
           " --steps 8 --batch 2 --input-size 128 --checkpoint-every 1 --warmup 2 --threads 1 "
           "--seed 5";
  };
  auto r = run_wheelpose(run(dir / "whole"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto killed = wheelpose::testing::run_killed_until_done(
      [&] {
        const bool resume = fs::exists(dir / "killed" / "checkpoint.pt");
        return run(dir / "killed") + (resume ? " --resume" : "");
      },
      1.0, 0.25);
  ASSERT_EQ(killed.failure, "");
  EXPECT_GE(killed.kills, 2);
  EXPECT_TRUE(same_bytes(dir / "whole" / "last.pt", dir / "killed" / "last.pt"));
  EXPECT_TRUE(same_bytes(dir / "whole" / "checkpoint.pt", dir / "killed" / "checkpoint.pt"));
  EXPECT_EQ(log_without_speed(dir / "whole" / "train_log.csv"),
            log_without_speed(dir / "killed" / "train_log.csv"));
}

// A run killed after its final checkpoint but before (or while) writing last.pt resumes to the
// same last.pt: the resume writes the checkpoint's weights out again.
TEST(TrainCli, ResumeAfterTheFinalCheckpointWritesLastWeights) {
  if (!have_models()) GTEST_SKIP() << "MoveNet models missing: run scripts/setup.sh";
  const auto dir = fresh_temp_dir("train_final");
  const fs::path gt = wheelpose::testing::write_coco_sample_gt(dir, true);
  auto r = run_wheelpose(small_run(gt, dir / "whole"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  fs::copy(dir / "whole", dir / "late");
  fs::remove(dir / "late" / "last.pt");
  r = run_wheelpose(small_run(gt, dir / "late") + " --resume");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(same_bytes(dir / "whole" / "last.pt", dir / "late" / "last.pt"));
  EXPECT_EQ(read_text(dir / "whole" / "train_log.csv"), read_text(dir / "late" / "train_log.csv"));
}

// keypoint AP from `wheelpose eval`'s metrics.json.
double keypoint_ap(const fs::path& metrics) {
  return json::parse(read_text(metrics))["results"]["keypoints"]["stats"]["AP"].get<double>();
}

// Validation scores the starting weights and every --val-every steps; best.pt holds the best
// row's weights, and `predict` + `eval` on them give the very number val_log.csv recorded. A run
// stopped and resumed logs the same validations.
TEST(TrainCli, ValidationKeepsTheBestWeightsAndMatchesPredictPlusEval) {
  if (!have_models()) GTEST_SKIP() << "MoveNet models missing: run scripts/setup.sh";
  const auto dir = fresh_temp_dir("train_val");
  const fs::path gt = wheelpose::testing::write_coco_sample_gt(dir, true);
  const std::string val = " --val " + gt.string() + " --val-every 2 --val-size 320";
  auto r = run_wheelpose(small_run(gt, dir / "whole") + val);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run_wheelpose(small_run(gt, dir / "parts") + val + " --stop-after 3");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run_wheelpose(small_run(gt, dir / "parts") + val + " --resume");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string val_log = read_text(dir / "whole" / "val_log.csv");
  EXPECT_EQ(val_log, read_text(dir / "parts" / "val_log.csv"));

  std::istringstream rows(val_log);
  std::string line;
  std::getline(rows, line);
  std::vector<std::pair<int, double>> scored;  // step, keypoint AP
  while (std::getline(rows, line)) {
    scored.emplace_back(std::stoi(line), std::stod(line.substr(line.find(',') + 1)));
  }
  ASSERT_EQ(scored.size(), 3u) << val_log;
  EXPECT_EQ(scored[0].first, 0);
  EXPECT_EQ(scored[1].first, 2);
  EXPECT_EQ(scored[2].first, 4);
  auto best = scored.begin();
  for (auto it = scored.begin(); it != scored.end(); ++it) {
    if (it->second > best->second) best = it;
  }
  const json best_json = json::parse(read_text(dir / "whole" / "best.json"));
  EXPECT_EQ(best_json["step"].get<int>(), best->first);

  r = run_wheelpose("predict --model " + (dir / "whole" / "best.pt").string() +
                    " --size 320 --coco " + gt.string() + " --images " + dir.string() + " --out " +
                    (dir / "best.json").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run_wheelpose("eval --gt " + gt.string() + " --dt " + (dir / "best.json").string() +
                    " --out " + (dir / "eval").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NEAR(keypoint_ap(dir / "eval" / "metrics.json"), best->second, 1e-6);
  EXPECT_NEAR(best_json["keypoint_ap"].get<double>(), best->second, 1e-6);
  EXPECT_EQ(read_text(dir / "whole" / "curves.png").substr(1, 3), "PNG");
}

// Two processes (Gloo, meeting at a file) train one run: each computes half of every batch,
// rank 0 writes the run, and a stopped two-process run resumed continues exactly.
TEST(TrainCli, TwoProcessesTrainOneRunAndResumeExactly) {
  if (!have_models()) GTEST_SKIP() << "MoveNet models missing: run scripts/setup.sh";
  const auto dir = fresh_temp_dir("train_parallel");
  const fs::path gt = wheelpose::testing::write_coco_sample_gt(dir, true);
  auto pair = [&](const fs::path& out, const std::string& extra, const std::string& store) {
    auto rank = [&](int r) {
      return run_wheelpose(small_run(gt, out) + " --world-size 2 --rank " + std::to_string(r) +
                           " --rendezvous file://" + (dir / store).string() + extra);
    };
    auto zero = std::async(std::launch::async, rank, 0);
    auto one = std::async(std::launch::async, rank, 1);
    const auto r0 = zero.get(), r1 = one.get();
    EXPECT_EQ(r0.exit_code, 0) << r0.output;
    EXPECT_EQ(r1.exit_code, 0) << r1.output;
  };
  pair(dir / "whole", "", "store_whole");
  const std::string log = log_without_speed(dir / "whole" / "train_log.csv");
  EXPECT_EQ(std::count(log.begin(), log.end(), '\n'), 5) << log;
  EXPECT_EQ(log.find("nan"), std::string::npos) << log;
  EXPECT_NE(read_text(dir / "whole" / "options.json").find("\"world_size\": 2"), std::string::npos);
  pair(dir / "parts", " --stop-after 2", "store_a");
  pair(dir / "parts", " --resume", "store_b");
  EXPECT_TRUE(same_bytes(dir / "whole" / "last.pt", dir / "parts" / "last.pt"));
  EXPECT_TRUE(same_bytes(dir / "whole" / "checkpoint.pt", dir / "parts" / "checkpoint.pt"));
  EXPECT_EQ(log, log_without_speed(dir / "parts" / "train_log.csv"));

  auto r = run_wheelpose(small_run(gt, dir / "odd") + " --world-size 3 --rank 0 --rendezvous " +
                         "file://" + (dir / "store_odd").string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("multiple of --world-size"), std::string::npos) << r.output;
}

TEST(TrainCli, BadInputIsOneLineAndLeavesTheCheckpoint) {
  if (!have_models()) GTEST_SKIP() << "MoveNet models missing: run scripts/setup.sh";
  const auto dir = fresh_temp_dir("train_bad");
  const fs::path gt = wheelpose::testing::write_coco_sample_gt(dir, true);

  std::ofstream(dir / "empty.json") << "";
  auto r = run_wheelpose("train --train " + (dir / "empty.json").string() + " --out " +
                         (dir / "x").string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("empty.json"), std::string::npos) << r.output;

  r = run_wheelpose(small_run(gt, dir / "capped") + " --max-relative-step -1");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("--max-relative-step must not be negative"), std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(dir / "capped"));
  r = run_wheelpose(small_run(gt, dir / "field") + " --offset-radius 9");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("--offset-radius must be 0 to 8"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "field"));

  json no_image = json::parse(read_text(gt));
  no_image["images"][0]["file_name"] = "missing.jpg";
  std::ofstream(dir / "no_image.json") << no_image.dump();
  r = run_wheelpose("train --train " + (dir / "no_image.json").string() + " --out " +
                    (dir / "y").string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("missing.jpg"), std::string::npos) << r.output;

  r = run_wheelpose(small_run(gt, dir / "run") + " --stop-after 1");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string checkpoint = read_text(dir / "run" / "checkpoint.pt");
  r = run_wheelpose(small_run(gt, dir / "run") + " --lr 0.001 --resume");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("other settings"), std::string::npos) << r.output;
  r = run_wheelpose(small_run(gt, dir / "run"));  // no --resume: refuses to overwrite
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("--resume"), std::string::npos) << r.output;
  EXPECT_EQ(read_text(dir / "run" / "checkpoint.pt"), checkpoint);

  json no_val_image = json::parse(read_text(gt));
  no_val_image["images"][0]["file_name"] = "gone.jpg";
  std::ofstream(dir / "no_val_image.json") << no_val_image.dump();
  r = run_wheelpose(small_run(gt, dir / "z") + " --val " + (dir / "no_val_image.json").string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("gone.jpg"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "z" / "checkpoint.pt"));
}

// The bad inputs for a rehearsal set: no people, a weight <= 0 and keypoints that do
// not fit the model are one line, exit 2, nothing written; an image that stops being readable
// mid-run is skipped with one warning naming it, and the run finishes the same way every time.
TEST(TrainCli, BadRehearsalSetsAndUnreadableImages) {
  if (!have_models()) GTEST_SKIP() << "MoveNet models missing: run scripts/setup.sh";
  const auto dir = fresh_temp_dir("train_rehearsal_bad");
  const fs::path gt = wheelpose::testing::write_coco_sample_gt(dir, true);
  const json sample = json::parse(read_text(gt));
  const auto refused = [&](const std::string& train, const std::string& message) {
    const auto r = run_wheelpose("train --train " + train + " --out " + (dir / "never").string());
    EXPECT_EQ(r.exit_code, 2) << train << ": " << r.output;
    EXPECT_NE(r.output.find(message), std::string::npos) << train << ": " << r.output;
    EXPECT_FALSE(fs::exists(dir / "never")) << train;
  };
  json nobody = sample;
  nobody["annotations"] = json::array();
  std::ofstream(dir / "nobody.json") << nobody.dump();
  refused((dir / "nobody.json").string(), "nobody.json: no person with a labelled keypoint");
  refused(gt.string() + ":0", "the weight after ':' must be a positive number");
  refused(gt.string() + ":-2", "the weight after ':' must be a positive number");
  json short_keypoints = sample;
  short_keypoints["annotations"][0]["keypoints"].erase(
      short_keypoints["annotations"][0]["keypoints"].end() - 3,
      short_keypoints["annotations"][0]["keypoints"].end());
  std::ofstream(dir / "short.json") << short_keypoints.dump();
  refused((dir / "short.json").string(),
          "short.json: annotations[0].keypoints: expected 51 numbers");

  // A second image, cut short: every draw of it trains on the next readable image instead.
  json two = sample;
  json cut_image = two["images"][0];
  cut_image["id"] = 777;
  cut_image["file_name"] = "cut.jpg";
  two["images"].push_back(cut_image);
  for (json a : sample["annotations"]) {
    a["id"] = a["id"].get<long>() + 100000;
    a["image_id"] = 777;
    two["annotations"].push_back(a);
  }
  const std::string photo = read_text(dir / sample["images"][0]["file_name"].get<std::string>());
  std::ofstream(dir / "cut.jpg", std::ios::binary) << photo.substr(0, 3000);
  std::ofstream(dir / "two.json") << two.dump();
  const auto a = run_wheelpose(small_run(dir / "two.json", dir / "a"));
  ASSERT_EQ(a.exit_code, 0) << a.output;
  const std::string warning =
      "skipping an image that cannot be read: " + (dir / "cut.jpg").string() + ": truncated JPEG";
  const auto first = a.output.find(warning);
  EXPECT_NE(first, std::string::npos) << a.output;
  EXPECT_EQ(a.output.find(warning, first + 1), std::string::npos) << "warned more than once";
  const auto b = run_wheelpose(small_run(dir / "two.json", dir / "b"));
  ASSERT_EQ(b.exit_code, 0) << b.output;
  EXPECT_TRUE(same_bytes(dir / "a" / "last.pt", dir / "b" / "last.pt"));
}

}  // namespace
