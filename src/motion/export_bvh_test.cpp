#include "motion/export_bvh.h"

#include <assimp/scene.h>
#include <gtest/gtest.h>

#include <assimp/Importer.hpp>
#include <filesystem>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/random.h"
#include "motion/export_test_support.h"

namespace wheelpose::motion {

namespace {

using export_test::make_test_motion;

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::vector<double> numbers_of(const std::string& line) {
  std::vector<double> values;
  std::istringstream in(line);
  for (double v; in >> v;) values.push_back(v);
  return values;
}

Eigen::Quaterniond from_zxy(const Eigen::Vector3d& a) {
  return Eigen::AngleAxisd(a.x(), Eigen::Vector3d::UnitZ()) *
         Eigen::AngleAxisd(a.y(), Eigen::Vector3d::UnitX()) *
         Eigen::AngleAxisd(a.z(), Eigen::Vector3d::UnitY());
}

TEST(ExportBvh, EulerZxyReproducesTheRotation) {
  RandomStream stream(7, {"euler_zxy"});
  for (int i = 0; i < 500; ++i) {
    const Eigen::Quaterniond q = Eigen::Quaterniond(stream.normal(0, 1), stream.normal(0, 1),
                                                    stream.normal(0, 1), stream.normal(0, 1))
                                     .normalized();
    const Eigen::Vector3d angles = euler_zxy(q);
    EXPECT_LE(std::abs(angles.y()), std::numbers::pi / 2 + 1e-12);
    EXPECT_LT(from_zxy(angles).angularDistance(q), 1e-9) << "draw " << i;
  }
  // Gimbal lock (x = ±90°) still reproduces the rotation.
  for (double x : {std::numbers::pi / 2, -std::numbers::pi / 2}) {
    const Eigen::Quaterniond q = from_zxy(Eigen::Vector3d(0.3, x, -0.7));
    EXPECT_LT(from_zxy(euler_zxy(q)).angularDistance(q), 1e-7);
  }
  // Hand-computed: a pure rotation about one axis lands in its own channel.
  const Eigen::Vector3d y90 = euler_zxy(
      Eigen::Quaterniond(Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitY())));
  EXPECT_NEAR(y90.x(), 0, 1e-12);
  EXPECT_NEAR(y90.y(), 0, 1e-12);
  EXPECT_NEAR(y90.z(), std::numbers::pi / 2, 1e-12);
}

TEST(ExportBvh, HierarchyTextIsAsDocumented) {
  const std::string text = bvh_text(make_test_motion(5, 30.0));
  const std::vector<std::string> lines = lines_of(text);
  ASSERT_GT(lines.size(), 10u);
  EXPECT_EQ(lines[0], "HIERARCHY");
  EXPECT_EQ(lines[1], "ROOT pelvis");
  EXPECT_EQ(lines[2], "{");
  EXPECT_EQ(lines[3], "  OFFSET 0.000000 0.000000 0.000000");
  EXPECT_EQ(lines[4], "  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation");
  EXPECT_EQ(lines[5], "  JOINT left_hip");
  EXPECT_EQ(lines[6], "  {");
  EXPECT_EQ(lines[7], "    OFFSET 0.100000 0.000000 0.000000");
  EXPECT_EQ(lines[8], "    CHANNELS 3 Zrotation Xrotation Yrotation");
  int joints = 0, end_sites = 0, roots = 0;
  std::size_t motion_line = 0;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (lines[i].find("JOINT ") != std::string::npos) ++joints;
    if (lines[i].find("End Site") != std::string::npos) ++end_sites;
    if (lines[i].rfind("ROOT ", 0) == 0) ++roots;
    if (lines[i] == "MOTION") motion_line = i;
  }
  EXPECT_EQ(roots, 1);
  EXPECT_EQ(joints, kJointCount - 1);
  EXPECT_EQ(end_sites, 5);  // head_top, both wrists, both toes
  EXPECT_NE(text.find("JOINT head_top\n"), std::string::npos);
  ASSERT_GT(motion_line, 0u);
  EXPECT_EQ(lines[motion_line + 1], "Frames: 5");
  EXPECT_EQ(lines[motion_line + 2], "Frame Time: 0.033333333");
  ASSERT_EQ(lines.size(), motion_line + 3 + 5);
  for (std::size_t f = 0; f < 5; ++f) {
    EXPECT_EQ(numbers_of(lines[motion_line + 3 + f]).size(), 6u + 3u * (kJointCount - 1));
  }
  EXPECT_EQ(text.find("-0.000000"), std::string::npos);
  EXPECT_EQ(text, bvh_text(make_test_motion(5, 30.0)));  // deterministic
}

TEST(ExportBvh, FrameValuesAreHandComputed) {
  // One frame: root at (1, 2, 3), left elbow bent 90° about +Y, everything else at rest.
  SkeletalMotion motion = make_test_motion(1, 20.0);
  motion.root_positions[0] = Eigen::Vector3d(1, 2, 3);
  motion.local_rotations[0].fill(Eigen::Quaterniond::Identity());
  motion.local_rotations[0][kLeftElbow] =
      Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitY());
  const std::string text = bvh_text(motion);
  const std::vector<std::string> lines = lines_of(text);
  // The joints appear depth-first from the pelvis; find the left elbow's channel slot.
  std::vector<std::string> order;
  for (const std::string& line : lines) {
    const auto at = line.find_first_not_of(' ');
    if (line.compare(at, 5, "ROOT ") == 0 || line.compare(at, 6, "JOINT ") == 0) {
      order.push_back(line.substr(line.find(' ', at) + 1));
    }
  }
  ASSERT_EQ(order.size(), static_cast<std::size_t>(kJointCount));
  const std::vector<double> values = numbers_of(lines.back());
  ASSERT_EQ(values.size(), 6u + 3u * (kJointCount - 1));
  EXPECT_EQ(values[0], 1.0);
  EXPECT_EQ(values[1], 2.0);
  EXPECT_EQ(values[2], 3.0);
  for (std::size_t i = 0; i < order.size(); ++i) {
    const std::size_t slot = 3 + 3 * i;
    const bool elbow = order[i] == "left_elbow";
    EXPECT_EQ(values[slot + 0], 0.0) << order[i];                 // Z
    EXPECT_EQ(values[slot + 1], 0.0) << order[i];                 // X
    EXPECT_EQ(values[slot + 2], elbow ? 90.0 : 0.0) << order[i];  // Y
  }
  EXPECT_EQ(lines[lines.size() - 2], "Frame Time: 0.050000000");
}

TEST(ExportBvh, AssimpPlaysItBackAsForwardKinematics) {
  const auto dir = export_test::temp_dir("bvh");
  const SkeletalMotion motion = make_test_motion(7, 30.0);
  write_bvh(motion, dir / "hand_made.bvh");
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile((dir / "hand_made.bvh").string(), 0);
  ASSERT_NE(scene, nullptr) << importer.GetErrorString();
  ASSERT_EQ(scene->mNumAnimations, 1u);
  const aiAnimation& animation = *scene->mAnimations[0];
  EXPECT_NEAR(animation.mDuration / export_test::ticks_per_second(animation), 6.0 / 30.0, 1e-6);
  for (unsigned c = 0; c < animation.mNumChannels; ++c) {
    EXPECT_EQ(animation.mChannels[c]->mNumRotationKeys, 7u);
  }
  // 6-decimal text: positions to a micrometre, angles to a micro-degree.
  export_test::expect_plays_like(*scene, motion, 1e-4);
}

TEST(ExportBvh, RejectsBadMotionsAndPaths) {
  SkeletalMotion motion = make_test_motion(3, 30.0);
  EXPECT_THROW(write_bvh(motion, "/nonexistent_dir/x.bvh"), Error);
  SkeletalMotion no_frames = motion;
  no_frames.local_rotations.clear();
  no_frames.root_positions.clear();
  try {
    bvh_text(no_frames);
    FAIL() << "no frames accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::kBadInput);
    EXPECT_NE(std::string(e.what()).find("hand_made"), std::string::npos) << e.what();
  }
  SkeletalMotion short_root = motion;
  short_root.root_positions.pop_back();
  EXPECT_THROW(bvh_text(short_root), Error);
  SkeletalMotion zero_fps = motion;
  zero_fps.fps = 0;
  EXPECT_THROW(bvh_text(zero_fps), Error);
  SkeletalMotion not_unit = motion;
  not_unit.local_rotations[1][kSpine].coeffs() *= 2.0;
  EXPECT_THROW(bvh_text(not_unit), Error);
}

}  // namespace
}  // namespace wheelpose::motion
