// End-to-end tests of `wheelpose realism`: a results file that is the ground truth finds everyone
// with OKS 1, a real-photo model finds the sample's skier, and bad input is one line.

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

// The sample's people as results: every keypoint where the ground truth has it.
void write_gt_as_results(const fs::path& gt, const fs::path& out, bool with_keypoints) {
  json results = json::array();
  const json root = json::parse(read_text(gt));  // kept alive: the loop reads into it
  for (const json& a : root["annotations"]) {
    json r = {{"image_id", a["image_id"]}, {"category_id", 1}, {"bbox", a["bbox"]}, {"score", 1}};
    if (with_keypoints) {
      json kp = a["keypoints"];
      for (std::size_t k = 2; k < kp.size(); k += 3) kp[k] = 1.0;
      r["keypoints"] = kp;
    }
    results.push_back(r);
  }
  std::ofstream(out) << results.dump();
}

TEST(RealismCli, TheGroundTruthIsFoundWithOksOne) {
  const auto dir = fresh_temp_dir("realism_gt");
  const fs::path gt = wheelpose::testing::write_coco_sample_gt(dir, /*copy_image=*/true);
  write_gt_as_results(gt, dir / "dt.json", true);
  const auto r = run_wheelpose("realism " + gt.string() + " --images " + dir.string() + " --dt " +
                               (dir / "dt.json").string() + " --out " + (dir / "report").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("| all | 1 | 100.0 % | 1.000 |"), std::string::npos) << r.output;
  const json report = json::parse(read_text(dir / "report" / "realism.json"));
  EXPECT_EQ(report["overall"]["people"], 1);
  EXPECT_EQ(report["overall"]["found"], 1);
  EXPECT_DOUBLE_EQ(report["overall"]["mean_oks"].get<double>(), 1.0);
  EXPECT_EQ(read_text(dir / "report" / "realism.md").rfind("# Realism: ", 0), 0u);
  // The image's licence is an attribute like any other.
  bool licence_group = false;
  for (const json& g : report["groups"]) licence_group |= g["key"] == "license";
  EXPECT_FALSE(licence_group) << "one-valued numbers say nothing";
}

TEST(RealismCli, MinVisibleLeavesOutPeopleWhoShowLess) {
  const auto dir = fresh_temp_dir("realism_visible");
  const fs::path gt = wheelpose::testing::write_coco_sample_gt(dir, /*copy_image=*/true);
  write_gt_as_results(gt, dir / "dt.json", true);
  // The skier shows all 17 keypoints; hide the left ankle (labelled, v = 1).
  json root = json::parse(read_text(gt));
  root["annotations"][0]["keypoints"][3 * 15 + 2] = 1;
  std::ofstream(dir / "hidden.json") << root.dump();
  const std::string base = "realism " + (dir / "hidden.json").string() + " --images " +
                           dir.string() + " --dt " + (dir / "dt.json").string();
  const auto shows16 = run_wheelpose(base + " --min-visible 16");
  ASSERT_EQ(shows16.exit_code, 0) << shows16.output;
  EXPECT_NE(shows16.output.find("| all | 1 | 100.0 % | 1.000 |"), std::string::npos);
  EXPECT_NE(shows16.output.find("## face_visible"), std::string::npos) << shows16.output;
  const auto shows17 = run_wheelpose(base + " --min-visible 17 --out " + (dir / "r").string());
  ASSERT_EQ(shows17.exit_code, 0) << shows17.output;
  EXPECT_NE(shows17.output.find("| all | 0 |"), std::string::npos) << shows17.output;
  const json report = json::parse(read_text(dir / "r" / "realism.json"));
  EXPECT_EQ(report["left_out"]["too_few_visible"], 1);
  EXPECT_EQ(report["options"]["min_visible_keypoints"], 17);
  const auto bad = run_wheelpose(base + " --min-visible 18");
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_NE(bad.output.find("--min-visible"), std::string::npos) << bad.output;
}

TEST(RealismCli, ARealPhotoModelFindsTheSkier) {
  if (!fs::exists(fs::path(WHEELPOSE_SOURCE_DIR) / "models" / "movenet-thunder.json")) {
    GTEST_SKIP() << "MoveNet models missing: run scripts/setup.sh";
  }
  const auto dir = fresh_temp_dir("realism_model");
  const fs::path gt = wheelpose::testing::write_coco_sample_gt(dir, /*copy_image=*/true);
  const auto r = run_wheelpose("realism " + gt.string() + " --images " + dir.string() +
                               " --model movenet-thunder --out " + (dir / "report").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json report = json::parse(read_text(dir / "report" / "realism.json"));
  EXPECT_EQ(report["overall"]["found"], 1) << r.output;
  EXPECT_GT(report["overall"]["mean_oks"].get<double>(), 0.7) << r.output;
  // Its predictions are kept, and judging them again gives the same report.
  const auto again = run_wheelpose("realism " + gt.string() + " --images " + dir.string() +
                                   " --dt " + (dir / "report" / "results.json").string() +
                                   " --out " + (dir / "again").string());
  ASSERT_EQ(again.exit_code, 0) << again.output;
  EXPECT_EQ(json::parse(read_text(dir / "again" / "realism.json"))["overall"], report["overall"]);
}

TEST(RealismCli, BadInputIsOneLine) {
  const auto dir = fresh_temp_dir("realism_bad");
  const fs::path gt = wheelpose::testing::write_coco_sample_gt(dir, /*copy_image=*/true);
  write_gt_as_results(gt, dir / "boxes.json", false);
  fs::create_directories(dir / "empty");
  std::ofstream(dir / "file") << "x";
  const struct {
    std::string args, says;
  } cases[] = {
      {(dir / "empty").string(), "empty: no annotations.json"},
      {gt.string(), "gt.json: a COCO file needs --images"},
      {(dir / "nothing.json").string() + " --images " + dir.string(),
       "nothing.json: no such dataset"},
      {gt.string() + " --images " + dir.string() + " --dt " + (dir / "boxes.json").string(),
       "boxes.json: the detections carry no keypoints"},
      {gt.string() + " --images " + dir.string() + " --dt " + (dir / "boxes.json").string() +
           " --out " + (dir / "file").string(),
       "file: cannot create directory"},
  };
  for (const auto& c : cases) {
    const auto r = run_wheelpose("realism " + c.args);
    EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.says), std::string::npos) << c.args << "\n" << r.output;
    EXPECT_EQ(r.output.find('\n'), r.output.size() - 1) << "one line: " << r.output;
  }
}

TEST(RealismCli, BoxesJudgeASetLabelledByBoxOnly) {
  const auto dir = fresh_temp_dir("realism_boxes");
  const fs::path gt = wheelpose::testing::write_coco_sample_gt(dir, /*copy_image=*/true);
  write_gt_as_results(gt, dir / "boxes.json", false);
  // The skier labelled by box only, as the dev photos of wheelchair users are.
  json root = json::parse(read_text(gt));
  for (json& a : root["annotations"]) {
    a.erase("keypoints");
    a["num_keypoints"] = 0;
  }
  std::ofstream(dir / "boxes-gt.json") << root.dump();
  const std::string base = "realism " + (dir / "boxes-gt.json").string() + " --images " +
                           dir.string() + " --dt " + (dir / "boxes.json").string() + " --boxes";
  const auto r = run_wheelpose(base + " --out " + (dir / "report").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("| all | 1 | 100.0 % | 1.000 |"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("mean box IoU"), std::string::npos) << r.output;
  const json report = json::parse(read_text(dir / "report" / "realism.json"));
  EXPECT_DOUBLE_EQ(report["overall"]["mean_iou"].get<double>(), 1.0);
  // --in-frame needs each image's size; the sample gives it, and the skier is clear of the border.
  const auto in_frame = run_wheelpose(base + " --in-frame");
  ASSERT_EQ(in_frame.exit_code, 0) << in_frame.output;
  EXPECT_NE(in_frame.output.find("| all | 1 | 100.0 % | 1.000 |"), std::string::npos);
  // Without --boxes nobody has keypoints to judge.
  const auto keypoints =
      run_wheelpose("realism " + (dir / "boxes-gt.json").string() + " --images " + dir.string() +
                    " --dt " + (dir / "boxes.json").string());
  EXPECT_EQ(keypoints.exit_code, 2) << keypoints.output;
}

}  // namespace
