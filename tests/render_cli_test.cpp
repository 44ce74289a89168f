// End-to-end tests of `wheelpose render`: the example scenes render into five decodable PNGs
// with correct ground truth, the result does not depend on --threads, and bad scenes give one
// clear error line and exit code 2.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <string>

#include "cli_runner.h"

namespace {

using wheelpose::testing::fresh_temp_dir;
using wheelpose::testing::read_text;
using wheelpose::testing::run_wheelpose;
namespace fs = std::filesystem;

const std::string kScenes = std::string(WHEELPOSE_SOURCE_DIR) + "/data/scenes";

void write(const fs::path& path, const std::string& text) { std::ofstream(path) << text; }

// A wall 2.5 m in front of the camera, 32×24 pixels.
const char* kWall = R"({
  "camera": {"position": [0, 0, 0], "width": 32, "height": 24},
  "meshes": [{"primitive": {"type": "box", "size": [20, 20, 0.5]}}],
  "materials": [{"diffuse": [0.5, 0.5, 0.5]}],
  "instances": [{"mesh": 0, "material": 0, "translation": [0, 0, -3], "instance_id": 4,
                 "semantic_id": 9}]
})";

TEST(RenderCli, WritesFivePngsWithGroundTruth) {
  const fs::path dir = fresh_temp_dir("render_cli_wall");
  write(dir / "wall.json", kWall);
  const auto r =
      run_wheelpose("render " + (dir / "wall.json").string() + " --out " + (dir / "out").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const cv::Mat rgb = cv::imread((dir / "out/rgb.png").string(), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(rgb.type(), CV_8UC3);
  EXPECT_EQ(rgb.cols, 32);
  EXPECT_EQ(rgb.rows, 24);
  const cv::Mat depth = cv::imread((dir / "out/depth.png").string(), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(depth.type(), CV_16U);
  EXPECT_EQ(depth.at<std::uint16_t>(12, 16), 2500);  // millimetres
  EXPECT_EQ(depth.at<std::uint16_t>(0, 0), 2500);
  const cv::Mat instance = cv::imread((dir / "out/instance.png").string(), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(instance.type(), CV_16U);
  EXPECT_EQ(instance.at<std::uint16_t>(5, 5), 4);
  const cv::Mat semantic = cv::imread((dir / "out/semantic.png").string(), cv::IMREAD_UNCHANGED);
  EXPECT_EQ(semantic.at<std::uint16_t>(5, 5), 9);
  const cv::Mat normals = cv::imread((dir / "out/normals.png").string(), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(normals.type(), CV_16UC3);
  // Facing the camera: camera-space (0, 0, 1) → (32768, 32768, 65535); PNG channels are BGR.
  EXPECT_EQ(normals.at<cv::Vec3w>(12, 16), cv::Vec3w(65535, 32768, 32768));
  // No temporary files are left behind.
  int files = 0;
  for (const auto& e : fs::directory_iterator(dir / "out")) files += e.is_regular_file();
  EXPECT_EQ(files, 5);
}

TEST(RenderCli, ExampleScenesRenderAndThreadsDoNotChangeTheImage) {
  const fs::path dir = fresh_temp_dir("render_cli_examples");
  const std::string scene = kScenes + "/sphere_on_floor.json";
  const auto one = run_wheelpose("render " + scene + " --out " + (dir / "one").string() +
                                 " --spp 2 --threads 1");
  ASSERT_EQ(one.exit_code, 0) << one.output;
  const auto two = run_wheelpose("render " + scene + " --out " + (dir / "two").string() +
                                 " --spp 2 --threads 2");
  ASSERT_EQ(two.exit_code, 0) << two.output;
  EXPECT_EQ(read_text(dir / "one/rgb.png"), read_text(dir / "two/rgb.png"));
  EXPECT_EQ(read_text(dir / "one/depth.png"), read_text(dir / "two/depth.png"));
  EXPECT_FALSE(read_text(dir / "one/rgb.png").empty());
  const auto room =
      run_wheelpose("render " + kScenes + "/textured_room.json --out " + (dir / "room").string());
  ASSERT_EQ(room.exit_code, 0) << room.output;
  const cv::Mat rgb = cv::imread((dir / "room/rgb.png").string());
  EXPECT_EQ(rgb.cols, 640);
  EXPECT_EQ(rgb.rows, 360);
}

void expect_bad_input(const std::string& scene_text, const std::string& needle,
                      const std::string& extra = "") {
  const fs::path dir = fresh_temp_dir("render_cli_bad");
  write(dir / "s.json", scene_text);
  std::ofstream(dir / "empty.png").close();
  const auto r = run_wheelpose("render " + (dir / "s.json").string() + " --out " +
                               (dir / "out").string() + extra);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find(needle), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("error: "), 0u) << r.output;
  EXPECT_EQ(r.output.find('\n'), r.output.size() - 1) << "one line: " << r.output;
  EXPECT_FALSE(fs::exists(dir / "out" / "rgb.png"));
}

TEST(RenderCli, BadScenesGiveOneClearLine) {
  expect_bad_input("{\"camera\": [", "s.json: malformed JSON");
  expect_bad_input(R"({"camera": {"width": -1}})", "s.json: /camera/width: must be in 1..16384");
  expect_bad_input(R"({"materials": [{"texture": {"kind": "image", "path": "nope.png"}}]})",
                   "s.json: /materials/0/texture/path: file");
  expect_bad_input(R"({"materials": [{"texture": {"kind": "image", "path": "empty.png"}}]})",
                   "s.json: /materials/0/texture/path: cannot read image");
  expect_bad_input(R"({"background": {"image": "empty.png"}})",
                   "/background/image: cannot read image");
}

TEST(RenderCli, BadFlagsAreUsageErrors) {
  const fs::path dir = fresh_temp_dir("render_cli_flags");
  write(dir / "wall.json", kWall);
  const auto r = run_wheelpose("render " + (dir / "wall.json").string() + " --out " +
                               (dir / "out").string() + " --spp 0");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--spp"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "out"));
  const auto more_lit = run_wheelpose("render " + (dir / "wall.json").string() + " --out " +
                                      (dir / "out").string() + " --spp 2 --light-samples 3");
  EXPECT_EQ(more_lit.exit_code, 2) << more_lit.output;
  EXPECT_NE(more_lit.output.find("--light-samples (3) must be between 1 and --spp (2)"),
            std::string::npos)
      << more_lit.output;
  EXPECT_FALSE(fs::exists(dir / "out"));
  const auto contrast = run_wheelpose("render " + (dir / "wall.json").string() + " --out " +
                                      (dir / "out").string() + " --adaptive-contrast 5");
  EXPECT_EQ(contrast.exit_code, 2) << contrast.output;
  EXPECT_NE(contrast.output.find("--adaptive-contrast"), std::string::npos) << contrast.output;
  EXPECT_FALSE(fs::exists(dir / "out"));
}

TEST(RenderCli, AdaptiveAntiAliasingIsReportedAndCanBeTurnedOff) {
  const fs::path dir = fresh_temp_dir("render_cli_adaptive");
  write(dir / "wall.json", kWall);
  const std::string base =
      "render " + (dir / "wall.json").string() + " --out " + (dir / "out").string() + " --spp 4";
  const auto adaptive = run_wheelpose(base);
  ASSERT_EQ(adaptive.exit_code, 0) << adaptive.output;
  EXPECT_EQ(adaptive.output.find("100.0 % of pixels took all"), std::string::npos)
      << adaptive.output;  // a plain wall: few pixels need more than one sample
  const auto uniform = run_wheelpose(base + " --adaptive-contrast -1");
  ASSERT_EQ(uniform.exit_code, 0) << uniform.output;
  EXPECT_NE(uniform.output.find("100.0 % of pixels took all"), std::string::npos) << uniform.output;
}

TEST(RenderCli, MissingSceneFileIsBadInput) {
  const fs::path dir = fresh_temp_dir("render_cli_missing");
  const auto r =
      run_wheelpose("render " + (dir / "none.json").string() + " --out " + (dir / "out").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("none.json"), std::string::npos) << r.output;
}

}  // namespace
