// End-to-end tests of `wheelpose body`.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include <nlohmann/json.hpp>

#include "cli_runner.h"

namespace wheelpose::testing {
namespace {

const std::string kAssets = std::string(" --assets ") + WHEELPOSE_SHARED_DIR + "/assets";

TEST(BodyCli, ExportWritesGlbAndJsonDeterministically) {
  const auto dir = fresh_temp_dir("body_export");
  const auto a = dir / "a.glb", b = dir / "b.glb";
  for (const auto& out : {a, b}) {
    const CliResult r = run_wheelpose(
        "body export --seed 5 --params age=70 wheelchair=sport --out " + out.string() + kAssets);
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  const std::string glb = read_text(a);
  ASSERT_GT(glb.size(), 100000u);
  EXPECT_EQ(glb.substr(0, 4), "glTF");
  EXPECT_EQ(glb, read_text(b));
  const auto json = nlohmann::json::parse(read_text(dir / "a.json"));
  EXPECT_DOUBLE_EQ(json["params"]["age"].get<double>(), 70.0);
  EXPECT_EQ(json["wheelchair"]["type"], "sport");
  EXPECT_EQ(json["coco_keypoints"].size(), 17u);
}

TEST(BodyCli, SampleWritesCountPeople) {
  const auto dir = fresh_temp_dir("body_sample");
  const CliResult r =
      run_wheelpose("body sample --count 2 --seed 3 --out " + dir.string() + kAssets);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_FALSE(read_text(dir / "person_0000.glb").empty());
  EXPECT_FALSE(read_text(dir / "person_0001.json").empty());
  EXPECT_NE(read_text(dir / "person_0000.json"), read_text(dir / "person_0001.json"));
  // Dressed from the installed proxies, and pictured on a contact sheet (2 people: 2 x 1 tiles).
  const auto description = nlohmann::json::parse(read_text(dir / "person_0000.json"));
  EXPECT_GE(description["proxies"].size(), 3u);
  const cv::Mat sheet = cv::imread((dir / "contact_sheet.png").string(), cv::IMREAD_COLOR);
  ASSERT_FALSE(sheet.empty());
  EXPECT_EQ(sheet.cols, 512);
  EXPECT_EQ(sheet.rows, 256);
  // Each tile shows somebody: not a flat grey picture.
  for (int tile = 0; tile < 2; ++tile) {
    cv::Scalar mean, stddev;
    cv::meanStdDev(sheet(cv::Rect(256 * tile, 0, 256, 256)), mean, stddev);
    EXPECT_GT(stddev[0], 10.0);
  }
}

TEST(BodyCli, BadInputsExitTwoWithOneLine) {
  const auto dir = fresh_temp_dir("body_bad");
  CliResult r = run_wheelpose("body export --seed 1 --params age=300 --out " +
                              (dir / "x.glb").string() + kAssets);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("age"), std::string::npos);
  r = run_wheelpose("body export --seed 1 --out " + (dir / "x.glb").string() +
                    " --assets /nonexistent");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("base.obj"), std::string::npos);
  r = run_wheelpose("body export --seed 1 --clip /nonexistent.json --out " +
                    (dir / "x.glb").string() + kAssets);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  r = run_wheelpose("body export --empty-wheelchair --params wheelchair=none --out " +
                    (dir / "x.glb").string() + kAssets);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("nothing to export"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "x.glb"));
}

TEST(BodyCli, EmptyWheelchair) {
  const auto dir = fresh_temp_dir("body_empty");
  const CliResult r = run_wheelpose(
      "body export --seed 2 --empty-wheelchair --params "
      "wheelchair=power --out " +
      (dir / "chair.glb").string() + kAssets);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(read_text(dir / "chair.glb").substr(0, 4), "glTF");
  const CliResult cc =
      run_wheelpose("body export --cc-by-wheelchair --out " + (dir / "cc.glb").string());
  ASSERT_EQ(cc.exit_code, 0) << cc.output;
  EXPECT_NE(cc.output.find("bgamage"), std::string::npos);
  EXPECT_GT(read_text(dir / "cc.glb").size(), 100000u);
}

}  // namespace
}  // namespace wheelpose::testing

namespace wheelpose::testing {
namespace {

TEST(BodyCli, PosesPersonByASeatedClipFrame) {
  const auto dir = fresh_temp_dir("body_clip");
  const std::string bvh = std::string(WHEELPOSE_SHARED_DIR) + "/data/bvh/131_01.bvh";
  CliResult r =
      run_wheelpose("motion convert " + bvh + " --out " + dir.string() + " --exports json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string clip = (dir / "131_01.json").string();
  std::vector<nlohmann::json> wrists;
  for (int frame : {0, 60}) {
    const auto out = dir / ("f" + std::to_string(frame) + ".glb");
    r = run_wheelpose("body export --seed 1 --clip " + clip + " --frame " + std::to_string(frame) +
                      " --out " + out.string() + kAssets);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    auto json = nlohmann::json::parse(read_text(dir / ("f" + std::to_string(frame) + ".json")));
    wrists.push_back(json["coco_keypoints"]["left_wrist"]);
  }
  EXPECT_NE(wrists[0], wrists[1]);  // the arm moves with the clip
  r = run_wheelpose("body export --seed 1 --clip " + clip + " --frame 100000 --out " +
                    (dir / "x.glb").string() + kAssets);
  EXPECT_EQ(r.exit_code, 2) << r.output;
}

}  // namespace
}  // namespace wheelpose::testing
