// End-to-end runs of `wheelpose motion` on the shared CMU BVH clips, a synthetic HumanML3D-layout
// .npy and the built-in library.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.h"
#include "motion/clip_json.h"
#include "motion/test_support.h"

namespace wheelpose::testing {
namespace {

namespace fs = std::filesystem;

const std::string kBvh = std::string(WHEELPOSE_SHARED_DIR) + "/data/bvh/131_01.bvh";

// A (T, 22, 3) float32 .npy in SMPL-22 order: our 23 joints minus neck_base.
void write_smpl22_npy(const fs::path& path, const std::vector<motion::Pose>& frames) {
  const int smpl_to_ours[22] = {0,  1,  2,  3,  4,  5,  6,  7,  8,  9,  10,
                                11, 12, 13, 14, 15, 16, 17, 18, 19, 20, 21};
  std::string header = "{'descr': '<f4', 'fortran_order': False, 'shape': (" +
                       std::to_string(frames.size()) + ", 22, 3), }";
  while ((10 + header.size() + 1) % 64 != 0) header += ' ';
  header += '\n';
  std::ofstream out(path, std::ios::binary);
  out.write("\x93NUMPY\x01\x00", 8);
  const std::uint16_t length = static_cast<std::uint16_t>(header.size());
  out.write(reinterpret_cast<const char*>(&length), 2);
  out << header;
  for (const auto& pose : frames) {
    for (int j : smpl_to_ours) {
      for (int axis = 0; axis < 3; ++axis) {
        const float value = static_cast<float>(pose[j][axis]);
        out.write(reinterpret_cast<const char*>(&value), 4);
      }
    }
  }
}

TEST(MotionCli, ConvertsBvhToJsonGlbAndBvh) {
  const fs::path out = fresh_temp_dir("motion_bvh");
  const CliResult result = run_wheelpose("motion convert " + kBvh + " --out " + out.string());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  for (const char* ext : {".json", ".glb", ".bvh"}) {
    EXPECT_GT(fs::file_size(out / (std::string("131_01") + ext)), 1000u) << ext;
  }
  const motion::SeatedClip clip = motion::read_seated_clip_json(out / "131_01.json");
  EXPECT_GT(clip.positions.size(), 100u);
  EXPECT_EQ(clip.provenance["source"], kBvh);
  for (const auto& pose : clip.positions) {
    // Upright and in metres (this CMU conversion has a short trunk: 0.5 m pelvis to crown).
    EXPECT_GT(pose[motion::kHeadTop].y(), pose[motion::kPelvis].y() + 0.25);
    EXPECT_GT(pose[motion::kLeftKnee].y(), pose[motion::kLeftHip].y());      // seated thighs
  }
  fs::remove_all(out);
}

TEST(MotionCli, ConvertsSyntheticHumanMl3dNpyAndPreviewsIt) {
  const fs::path out = fresh_temp_dir("motion_npy");
  write_smpl22_npy(out / "walk.npy", motion::testing::synthetic_clip(60, 20, 5, 0.3).frames);
  CliResult result =
      run_wheelpose("motion convert " + (out / "walk.npy").string() + " --out " +
                    (out / "clips").string() + " --exports json,glb,bvh,fbx,fbx-ascii");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  for (const char* ext : {".json", ".glb", ".bvh", ".fbx", ".ascii.fbx"}) {
    EXPECT_TRUE(fs::exists(out / "clips" / (std::string("walk") + ext))) << ext;
  }
  // fbx is binary FBX (what Blender and Unity import); fbx-ascii the same document as text.
  char head[20] = {};
  std::ifstream(out / "clips" / "walk.fbx", std::ios::binary).read(head, 20);
  EXPECT_EQ(std::string(head, 20), "Kaydara FBX Binary  ");
  std::ifstream(out / "clips" / "walk.ascii.fbx", std::ios::binary).read(head, 20);
  EXPECT_EQ(std::string(head, 20), "; FBX 7.4.0 project ");
  result = run_wheelpose("motion preview " + (out / "clips" / "walk.json").string() + " --out " +
                         (out / "walk.gif").string());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  std::ifstream gif(out / "walk.gif", std::ios::binary);
  char magic[6] = {};
  gif.read(magic, 6);
  EXPECT_EQ(std::string(magic, 6), "GIF89a");
  fs::remove_all(out);
}

TEST(MotionCli, ABrokenClipIsRejectedAndTheOthersStillConvert) {
  const fs::path out = fresh_temp_dir("motion_broken");
  auto frames = motion::testing::synthetic_clip(40, 20, 5, 0.3).frames;
  write_smpl22_npy(out / "good.npy", frames);
  frames[10][motion::kLeftWrist].x() = std::nan("");
  write_smpl22_npy(out / "bad.npy", frames);
  std::ofstream(out / "short.npy") << "not a numpy file";
  const CliResult result =
      run_wheelpose("motion convert " + (out / "good.npy").string() + " " +
                    (out / "bad.npy").string() + " " + (out / "short.npy").string() + " --out " +
                    (out / "clips").string());
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("bad.npy"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("short.npy"), std::string::npos) << result.output;
  EXPECT_TRUE(fs::exists(out / "clips" / "good.json"));
  EXPECT_FALSE(fs::exists(out / "clips" / "bad.json"));
  for (const auto& entry : fs::directory_iterator(out / "clips")) {
    EXPECT_EQ(entry.path().string().find(".tmp"), std::string::npos) << entry.path();
  }
  fs::remove_all(out);
}

TEST(MotionCli, AClipNamedWhatFbxCannotHoldIsOneErrorAndNoFiles) {
  const fs::path out = fresh_temp_dir("motion_fbx_name");
  const auto frames = motion::testing::synthetic_clip(40, 20, 5, 0.3).frames;
  write_smpl22_npy(out / "Model::walk.npy", frames);
  write_smpl22_npy(out / "good.npy", frames);
  const CliResult result = run_wheelpose("motion convert " + (out / "Model::walk.npy").string() +
                                         " " + (out / "good.npy").string() + " --out " +
                                         (out / "clips").string() + " --exports json,glb,bvh,fbx");
  EXPECT_EQ(result.exit_code, 2) << result.output;
  std::size_t lines_naming_it = 0;
  std::istringstream lines(result.output);
  for (std::string line; std::getline(lines, line);) {
    if (line.find("Model::walk") != std::string::npos) {
      ++lines_naming_it;
      EXPECT_NE(line.find("cannot write FBX"), std::string::npos) << line;
    }
  }
  EXPECT_EQ(lines_naming_it, 1u) << result.output;
  // The clip is written in every format or in none; the good one in all four.
  std::vector<std::string> files;
  for (const auto& entry : fs::directory_iterator(out / "clips")) {
    files.push_back(entry.path().filename().string());
  }
  std::sort(files.begin(), files.end());
  EXPECT_EQ(files, (std::vector<std::string>{"good.bvh", "good.fbx", "good.glb", "good.json"}));
  fs::remove_all(out);
}

TEST(MotionCli, LibraryWritesEveryClipDeterministically) {
  const fs::path out = fresh_temp_dir("motion_library");
  CliResult result = run_wheelpose("motion library --out " + (out / "a").string() +
                                   " --seed 4 --exports json");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  result = run_wheelpose("motion library --out " + (out / "b").string() + " --seed 4 --exports json");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  int clips = 0;
  for (const auto& entry : fs::directory_iterator(out / "a")) {
    if (entry.path().filename() == "library.json") continue;
    ++clips;
    const std::string a = read_text(entry.path());
    const std::string b = read_text(out / "b" / entry.path().filename());
    EXPECT_EQ(a, b) << entry.path();
  }
  EXPECT_GE(clips, 40);
  fs::remove_all(out);
}

TEST(MotionCli, BadUsageAndConfigExitWithTwo) {
  const fs::path out = fresh_temp_dir("motion_usage");
  EXPECT_EQ(run_wheelpose("motion convert").exit_code, 2);
  EXPECT_EQ(run_wheelpose("motion convert x.bvh --out " + out.string() + " --exports png").exit_code,
            2);
  std::ofstream(out / "bad.yaml") << "motion:\n  filter:\n    cutoff: 5\n";
  const CliResult result = run_wheelpose("motion convert " + kBvh + " --out " + out.string() +
                                         " --config " + (out / "bad.yaml").string());
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.output.find("bad.yaml:3: key 'motion.filter.cutoff': unknown key"),
            std::string::npos)
      << result.output;
  fs::remove_all(out);
}

}  // namespace
}  // namespace wheelpose::testing
