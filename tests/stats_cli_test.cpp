// End-to-end tests of `wheelpose stats` on a small hand-made dataset (with camera metadata) and
// the shared COCO sample as the reference.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>

#include "cli_runner.h"

namespace {

using nlohmann::json;
using wheelpose::testing::fresh_temp_dir;
using wheelpose::testing::read_text;
using wheelpose::testing::run_wheelpose;
namespace fs = std::filesystem;

const std::string kSample =
    std::string(WHEELPOSE_SHARED_DIR) + "/data/coco-sample/person_keypoints_sample.json";

constexpr double kDeg = std::numbers::pi / 180;

json keypoints(int v_nose, int v_rest, double x, double y) {
  json kp = json::array();
  for (int k = 0; k < 17; ++k) {
    const int v = k == 0 ? v_nose : v_rest;
    kp.insert(kp.end(), {v ? x : 0, v ? y : 0, v});
  }
  return kp;
}

// Image 1 (100x100, camera 4.5 m from person A's nose at elevation 32 deg, azimuth 47 deg to
// A's right): A (all visible, with keypoints_3d) and B (nose occluded, no 3D). Image 2
// (200x100): C (no labelled keypoint) and a crowd region. Image 3: nobody.
json small_dataset() {
  const double d = 4.5, el = 32 * kDeg, az = 47 * kDeg;
  const double h = d * std::cos(el);
  // Person faces +Z with left = +X, so "right" is -X.
  const double cx = -h * std::sin(az), cy = 1.5 + d * std::sin(el), cz = h * std::cos(az);
  json extrinsics = {1, 0, 0, cx, 0, 1, 0, cy, 0, 0, 1, cz, 0, 0, 0, 1};
  // keypoints_3d are in camera space: world minus the camera position (no rotation).
  json k3 = json::array();
  auto add = [&](double x, double y, double z) { k3.insert(k3.end(), {x - cx, y - cy, z - cz}); };
  for (int k = 0; k < 17; ++k) {
    if (k == 0)
      add(0.0, 1.5, 0.0);
    else if (k == 11)
      add(0.1, 1.0, 0.0);  // left hip
    else if (k == 12)
      add(-0.1, 1.0, 0.0);  // right hip
    else
      add(0.0, 1.2, 0.0);
  }
  json a = {{"id", 1},
            {"image_id", 1},
            {"category_id", 1},
            {"bbox", {10, 10, 50, 80}},
            {"area", 4000},
            {"iscrowd", 0},
            {"num_keypoints", 17},
            {"keypoints", keypoints(2, 2, 35, 20)},
            {"keypoints_3d", k3}};
  json b = {
      {"id", 2},     {"image_id", 1}, {"category_id", 1},    {"bbox", {0, 0, 25, 25}},
      {"area", 600}, {"iscrowd", 0},  {"num_keypoints", 17}, {"keypoints", keypoints(1, 2, 5, 5)}};
  json c = {
      {"id", 3},     {"image_id", 2}, {"category_id", 1},   {"bbox", {100, 50, 20, 20}},
      {"area", 400}, {"iscrowd", 0},  {"num_keypoints", 0}, {"keypoints", keypoints(0, 0, 0, 0)}};
  json crowd = c;
  crowd["id"] = 4;
  crowd["iscrowd"] = 1;
  return {{"images",
           {{{"id", 1},
             {"file_name", "1.png"},
             {"width", 100},
             {"height", 100},
             {"camera", {{"extrinsics", extrinsics}}}},
            {{"id", 2}, {"file_name", "2.png"}, {"width", 200}, {"height", 100}},
            {{"id", 3}, {"file_name", "3.png"}, {"width", 100}, {"height", 100}}}},
          {"annotations", {a, b, c, crowd}},
          {"categories", json::parse(read_text(kSample))["categories"]}};
}

int nonzero_bin(const json& counts) {
  for (std::size_t i = 0; i < counts.size(); ++i) {
    if (counts[i] != 0) return static_cast<int>(i);
  }
  return -1;
}

TEST(Stats, NumbersByHandAndFigures) {
  const fs::path dir = fresh_temp_dir("stats_small");
  std::ofstream(dir / "small.json") << small_dataset().dump();
  const auto r =
      run_wheelpose("stats " + (dir / "small.json").string() + " --reference " + kSample +
                    " --label ours --reference-label COCO --out " + (dir / "out").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json s = json::parse(read_text(dir / "out" / "stats.json"));
  const json& ours = s["datasets"][0];
  const json& coco = s["datasets"][1];
  EXPECT_EQ(ours["label"], "ours");
  EXPECT_EQ(
      ours["counts"],
      json(
          {{"images", 3}, {"instances", 3}, {"labelled_instances", 2}, {"images_with_people", 2}}));
  EXPECT_EQ(ours["boxes_per_image"]["counts"], json({1, 1}));
  // sqrt(4000/1e4) = 0.632 -> bin 12; sqrt(625/1e4) = 0.25 -> 5; sqrt(400/2e4) = 0.141 -> 2.
  json sizes = json::array();
  for (int i = 0; i < 20; ++i) sizes.push_back(i == 12 || i == 5 || i == 2 ? 1 : 0);
  EXPECT_EQ(ours["relative_box_size"]["counts"], sizes);
  // Centres (0.35, 0.5), (0.125, 0.125), (0.55, 0.6) on a 32x32 grid.
  const json& centres = ours["box_centre"]["counts"];
  EXPECT_EQ(centres[16 * 32 + 11], 1);
  EXPECT_EQ(centres[4 * 32 + 4], 1);
  EXPECT_EQ(centres[19 * 32 + 17], 1);
  EXPECT_EQ(ours["keypoint_visibility"]["occluded"][0], 0.5);
  EXPECT_EQ(ours["keypoint_visibility"]["visible"][0], 0.5);
  EXPECT_EQ(ours["keypoint_visibility"]["visible"][5], 1.0);
  EXPECT_EQ(ours["keypoint_visibility"]["not_visible"][5], 0.0);
  // Nose of A at box-relative (0.5, 0.125) on 24x24: column 12, row 3.
  EXPECT_EQ(ours["keypoint_location"]["nose"]["counts"][3 * 24 + 12], 1);
  // Camera: elevation 32 deg -> bin floor((32+90)/5) = 24; azimuth 47 -> floor(227/10) = 22;
  // distance 4.5 on [0, 5] in 30 bins -> 27.
  const json& cam = ours["camera"];
  ASSERT_TRUE(cam["available"].get<bool>()) << cam.dump();
  EXPECT_EQ(nonzero_bin(cam["elevation_rad"]["counts"]), 24);
  EXPECT_EQ(nonzero_bin(cam["azimuth_rad"]["counts"]), 22);
  EXPECT_EQ(cam["distance_m"]["hi"], 5.0);
  EXPECT_EQ(nonzero_bin(cam["distance_m"]["counts"]), 27);
  EXPECT_EQ(cam["note"],
            "1 of 2 people in images with a camera lack keypoints_3d (nose and hips); skipped");
  EXPECT_NEAR(cam["directions_every_100th"][0][1].get<double>(), std::sin(32 * kDeg), 1e-9);
  // Reference: the COCO sample.
  EXPECT_EQ(coco["counts"], json({{"images", 4},
                                  {"instances", 14},
                                  {"labelled_instances", 12},
                                  {"images_with_people", 4}}));
  EXPECT_EQ(coco["camera"]["note"], "no image has camera.extrinsics; camera analysis skipped");
  // Figures in both formats, and the page shows each.
  const std::string html = read_text(dir / "out" / "index.html");
  for (const char* f : {"boxes_per_image", "relative_box_size", "box_location",
                        "keypoint_visibility", "keypoint_location", "camera"}) {
    const std::string png = read_text(dir / "out" / (std::string(f) + ".png"));
    ASSERT_GT(png.size(), 1000u) << f;
    EXPECT_EQ(png.substr(1, 3), "PNG") << f;
    EXPECT_NE(read_text(dir / "out" / (std::string(f) + ".svg")).find("<svg"), std::string::npos)
        << f;
    EXPECT_NE(html.find("src=\"" + std::string(f) + ".png\""), std::string::npos) << f;
  }
}

TEST(Stats, BoxesPerImageOfTheSample) {
  const fs::path dir = fresh_temp_dir("stats_sample");
  const auto r = run_wheelpose("stats " + kSample + " --out " + (dir / "out").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json s = json::parse(read_text(dir / "out" / "stats.json"));
  // Images have 1, 3, 5 and 5 people.
  EXPECT_EQ(s["datasets"][0]["boxes_per_image"]["counts"], json({1, 0, 1, 0, 2}));
  EXPECT_FALSE(fs::exists(dir / "out" / "camera.png"));
  EXPECT_EQ(s["figures"].size(), 5u);
}

TEST(Stats, Deterministic) {
  const fs::path dir = fresh_temp_dir("stats_determinism");
  std::ofstream(dir / "small.json") << small_dataset().dump();
  for (const char* out : {"a", "b"}) {
    ASSERT_EQ(run_wheelpose("stats " + (dir / "small.json").string() + " --reference " + kSample +
                            " --out " + (dir / out).string())
                  .exit_code,
              0);
  }
  EXPECT_EQ(read_text(dir / "a" / "stats.json"), read_text(dir / "b" / "stats.json"));
  EXPECT_EQ(read_text(dir / "a" / "box_location.png"), read_text(dir / "b" / "box_location.png"));
}

TEST(Stats, BrokenInputsAreNamed) {
  const fs::path dir = fresh_temp_dir("stats_broken");
  std::ofstream(dir / "broken.json") << "{\"images\": [1, 2";
  auto r =
      run_wheelpose("stats " + (dir / "broken.json").string() + " --out " + (dir / "o").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(
      r.output.find("error: " + (dir / "broken.json").string() + ": malformed JSON at line 1"),
      std::string::npos)
      << r.output;
  json bad = small_dataset();
  bad["annotations"][1]["keypoints"].erase(0);
  std::ofstream(dir / "short.json") << bad.dump();
  r = run_wheelpose("stats " + (dir / "short.json").string() + " --out " + (dir / "o").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(
      r.output.find("error: " + (dir / "short.json").string() +
                    ": annotations[1].keypoints: expected 51 numbers (17 keypoints x 3), got 50"),
      std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(dir / "o" / "stats.json"));
}

}  // namespace
