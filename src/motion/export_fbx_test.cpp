#include "motion/export_fbx.h"

#include <assimp/scene.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <assimp/Importer.hpp>
#include <cmath>
#include <filesystem>
#include <functional>
#include <map>
#include <numbers>
#include <string>

#include "core/atomic_file.h"
#include "core/error.h"
#include "motion/euler_curves.h"
#include "motion/export_test_support.h"
#include "motion/fbx_test_reader.h"
#include "motion/fbx_test_scene.h"
#include "motion/fbx_time.h"
#include "motion/library.h"
#include "motion/pipeline.h"
#include "motion/test_support.h"

namespace wheelpose::motion {

namespace {

using export_test::make_test_motion;
using export_test::temp_dir;
using fbx::Node;
using fbx::testing::child;
using fbx::testing::FbxScene;
using fbx::testing::name_of;
using fbx::testing::property;
using fbx::testing::top;
using fbx::testing::value;
using fbx::testing::world_transforms;

constexpr double kDegrees = 180.0 / std::numbers::pi;

// World positions of the joints at `tick`, evaluating the curves as the FBX SDK would.
Pose play(const FbxScene& scene, std::int64_t tick) {
  const auto world = world_transforms(scene, tick);
  Pose pose;
  for (const Node* model : scene.of_type("Model")) {
    if (auto joint = joint_from_name(name_of(*model))) {
      pose[*joint] = world.at(value<std::int64_t>(*model)).translation();
    }
  }
  return pose;
}

// Forward kinematics at a fractional frame: root lerped, local rotations slerped (what glTF
// players do between keys).
Pose reference_pose(const SkeletalMotion& motion, double frame) {
  const auto k = static_cast<std::size_t>(std::floor(frame));
  const std::size_t next = std::min(k + 1, motion.frame_count() - 1);
  const double w = frame - static_cast<double>(k);
  SkeletalMotion one = motion;
  one.root_positions = {(1 - w) * motion.root_positions[k] + w * motion.root_positions[next]};
  PoseRotations rotations;
  for (int j = 0; j < kJointCount; ++j) {
    rotations[j] = motion.local_rotations[k][j].slerp(w, motion.local_rotations[next][j]);
  }
  one.local_rotations = {rotations};
  return forward_kinematics(one, 0);
}

double max_error(const Pose& a, const Pose& b) {
  double worst = 0;
  for (int j = 0; j < kJointCount; ++j) worst = std::max(worst, (a[j] - b[j]).norm());
  return worst;
}

std::vector<Node> read_written(const SkeletalMotion& motion, const std::string& dir_name) {
  const auto dir = temp_dir(dir_name);
  write_fbx(motion, dir / "motion.fbx");
  return fbx::testing::read_binary(read_file(dir / "motion.fbx"));
}

TEST(ExportFbx, BinaryFileIsTheDocumentAndStable) {
  const auto dir = temp_dir("fbx_binary");
  const SkeletalMotion motion = make_test_motion(9, 30.0);
  write_fbx(motion, dir / "a.fbx");
  const std::string bytes = read_file(dir / "a.fbx");
  EXPECT_EQ(bytes.substr(0, 20), "Kaydara FBX Binary  ");
  std::uint32_t version = 0;
  EXPECT_TRUE(fbx::testing::read_binary(bytes, &version) ==
              fbx_document(motion, FbxEncoding::kBinary));
  EXPECT_EQ(version, 7400u);
  write_fbx(motion, dir / "b.fbx");
  EXPECT_TRUE(read_file(dir / "b.fbx") == bytes);
}

TEST(ExportFbx, SpansAndTimeModeMatchTheClip) {
  // 3.9 s at 30 fps and 8.275 s at 120 fps: the ASCII export used to say 3 s and 8 s, with
  // TimeSpanStop 1 s and TimeMode 24 fps. 20 fps has no TimeMode entry: custom.
  struct Case {
    int frames;
    double fps;
    std::int32_t mode;
    std::int64_t stop;
  };
  for (const Case& c : {Case{118, 30, 6, 180126016200}, Case{994, 120, 1, 382190457450},
                        Case{61, 20, 14, 3 * kFbxTicksPerSecond}}) {
    const SkeletalMotion motion = testing::synthetic_motion(c.frames, c.fps, 2);
    const std::vector<Node> document = read_written(motion, "fbx_span");
    const Node& settings = child(top(document, "GlobalSettings"), "Properties70");
    EXPECT_EQ(value<std::int32_t>(property(settings, "TimeMode"), 4), c.mode) << c.fps;
    EXPECT_EQ(value<double>(property(settings, "CustomFrameRate"), 4), c.fps);
    EXPECT_EQ(value<std::int64_t>(property(settings, "TimeSpanStart"), 4), 0);
    EXPECT_EQ(value<std::int64_t>(property(settings, "TimeSpanStop"), 4), c.stop) << c.fps;
    const FbxScene scene(document);
    ASSERT_EQ(scene.of_type("AnimationStack").size(), 1u);
    const Node& stack = child(*scene.of_type("AnimationStack")[0], "Properties70");
    EXPECT_EQ(value<std::int64_t>(property(stack, "LocalStart"), 4), 0);
    EXPECT_EQ(value<std::int64_t>(property(stack, "ReferenceStart"), 4), 0);
    EXPECT_EQ(value<std::int64_t>(property(stack, "LocalStop"), 4), c.stop);
    EXPECT_EQ(value<std::int64_t>(property(stack, "ReferenceStop"), 4), c.stop);
    const Node& take = child(top(document, "Takes"), "Take");
    EXPECT_EQ(value<std::int64_t>(child(take, "LocalTime"), 1), c.stop);
    EXPECT_EQ(value<std::int64_t>(child(take, "ReferenceTime"), 1), c.stop);
  }
}

TEST(ExportFbx, EveryKeyIsExactLinearAndContinuous) {
  const SkeletalMotion motion = testing::synthetic_motion(118, 30, 4, 1.5);
  const FbxScene scene(read_written(motion, "fbx_keys"));
  const FrameRate rate = exact_frame_rate(30);
  const std::vector<const Node*> curves = scene.of_type("AnimationCurve");
  // Pelvis translation + every joint's rotation, three channels each.
  ASSERT_EQ(curves.size(), static_cast<std::size_t>(3 * (kJointCount + 1)));
  for (const Node* curve : curves) {
    const auto& times = value<std::vector<std::int64_t>>(child(*curve, "KeyTime"));
    ASSERT_EQ(times.size(), motion.frame_count());
    for (std::size_t f = 0; f < times.size(); ++f) {
      ASSERT_EQ(times[f], static_cast<std::int64_t>(f) * 1539538600) << "frame " << f;
      ASSERT_EQ(times[f], fbx_frame_time(static_cast<std::int64_t>(f), rate));
    }
    EXPECT_EQ(value<std::vector<std::int32_t>>(child(*curve, "KeyAttrFlags")),
              std::vector<std::int32_t>{24836});
    EXPECT_EQ(value<std::vector<std::int32_t>>(child(*curve, "KeyAttrRefCount")),
              std::vector<std::int32_t>{static_cast<std::int32_t>(times.size())});
    EXPECT_EQ(value<std::vector<float>>(child(*curve, "KeyAttrDataFloat")).size(), 4u);
  }
  for (const Node* curve_node : scene.of_type("AnimationCurveNode")) {
    if (name_of(*curve_node) != "R") continue;
    for (const auto& [curve, channel] :
         scene.children_of(value<std::int64_t>(*curve_node), "AnimationCurve")) {
      const auto& values = value<std::vector<float>>(child(*curve, "KeyValueFloat"));
      for (std::size_t k = 1; k < values.size(); ++k) {
        EXPECT_LE(std::abs(values[k] - values[k - 1]), 180.0f) << channel << " key " << k;
      }
    }
  }
}

// Largest joint error of the FBX played back as the FBX SDK does (linear curves in each model's
// rotation order) at every key and halfway between keys, against forward kinematics of the
// clip's rotations slerped between frames.
std::pair<double, double> playback_error(const SkeletalMotion& motion) {
  const FbxScene scene(fbx_document(motion, FbxEncoding::kBinary));
  const FrameRate rate = exact_frame_rate(motion.fps);
  double on_keys = 0, between = 0;
  for (std::size_t f = 0; f < motion.frame_count(); ++f) {
    const auto tick = fbx_frame_time(static_cast<std::int64_t>(f), rate);
    on_keys = std::max(on_keys, max_error(play(scene, tick), forward_kinematics(motion, f)));
    if (f + 1 < motion.frame_count()) {
      const auto next = fbx_frame_time(static_cast<std::int64_t>(f + 1), rate);
      between = std::max(between, max_error(play(scene, (tick + next) / 2),
                                            reference_pose(motion, static_cast<double>(f) + 0.5)));
    }
  }
  return {on_keys, between};
}

TEST(ExportFbx, PlaysBackWithinAMillimetreOnAndBetweenKeys) {
  for (double fps : {30.0, 20.0}) {
    const auto [on_keys, between] = playback_error(testing::synthetic_motion(60, fps, 9, 0.3));
    EXPECT_LT(on_keys, 1e-5) << fps;
    EXPECT_LT(between, 1e-3) << fps;
  }
}

TEST(ExportFbx, LibraryClipsPlayBackWithinAMillimetreBetweenKeys) {
  // Linear Euler curves and slerp part by about the square of the turn between keys: within
  // 1 mm for every clip whose joints turn less than 12° per frame; tennis_serve's arm turns 15°.
  for (const auto& info : library_motions()) {
    const SeatedClip clip = run_motion_pipeline(library_clip(info.id, 3), MotionOptions{});
    double fastest = 0;
    for (std::size_t k = 1; k < clip.motion.frame_count(); ++k) {
      for (int j = 0; j < kJointCount; ++j) {
        fastest = std::max(fastest, clip.motion.local_rotations[k][j].angularDistance(
                                        clip.motion.local_rotations[k - 1][j]));
      }
    }
    const auto [on_keys, between] = playback_error(clip.motion);
    EXPECT_LT(on_keys, 1e-5) << info.id;
    EXPECT_LT(between, fastest * kDegrees < 12 ? 1e-3 : 2.5e-3)
        << info.id << ", fastest joint " << fastest * kDegrees << "° per frame";
  }
}

TEST(ExportFbx, AssimpReadsBinaryAndAsciiAlike) {
  const auto dir = temp_dir("fbx_assimp");
  const SkeletalMotion motion = make_test_motion(9, 30.0);
  write_fbx(motion, dir / "binary.fbx");
  write_fbx_ascii(motion, dir / "ascii.fbx");
  const std::string text = read_file(dir / "ascii.fbx");
  EXPECT_EQ(text.rfind("; FBX 7.4.0 project file", 0), 0u);
  EXPECT_NE(text.find("P: \"UnitScaleFactor\", \"double\", \"Number\", \"\", 100\n"),
            std::string::npos);
  EXPECT_NE(text.find("P: \"TimeSpanStop\", \"KTime\", \"Time\", \"\", 12316308800\n"),
            std::string::npos);
  EXPECT_NE(text.find("AnimationStack: "), std::string::npos);
  EXPECT_NE(text.find("\"AnimStack::hand_made\""), std::string::npos);
  for (const char* name : {"binary.fbx", "ascii.fbx"}) {
    Assimp::Importer importer;
    const aiScene* scene = importer.ReadFile((dir / name).string(), 0);
    ASSERT_NE(scene, nullptr) << name << ": " << importer.GetErrorString();
    ASSERT_EQ(scene->mNumAnimations, 1u) << name;
    const aiAnimation& animation = *scene->mAnimations[0];
    EXPECT_NEAR(animation.mDuration / export_test::ticks_per_second(animation), 8 / 30.0, 1e-6)
        << name;
    export_test::expect_plays_like(*scene, motion, 1e-4);
    ASSERT_EQ(scene->mNumMeshes, 1u);
    EXPECT_EQ(scene->mMeshes[0]->mNumBones, static_cast<unsigned>(kJointCount)) << name;
  }
}

TEST(ExportFbx, BadInputIsOneErrorAndNoFile) {
  const auto dir = temp_dir("fbx_bad");
  const SkeletalMotion good = make_test_motion(3, 30.0);
  struct Case {
    const char* what;
    SkeletalMotion motion;
    const char* message;
  };
  std::vector<Case> cases;
  SkeletalMotion m = good;
  m.local_rotations.clear();
  m.root_positions.clear();
  cases.push_back({"no frames", m, "no frames"});
  m = good;
  m.fps = 0;
  cases.push_back({"fps 0", m, "fps must be a positive number"});
  m.fps = std::nan("");
  cases.push_back({"fps NaN", m, "fps must be a positive number"});
  m = good;
  m.fps = 1e9;
  cases.push_back({"fps huge", m, "outside what FBX time can hold"});
  m = good;
  m.name = std::string("bad\x00\x01name", 9);
  cases.push_back({"class separator bytes", m, "contains a control character"});
  m.name = "Model::pelvis";
  cases.push_back({"ASCII class separator", m, "contains '::'"});
  m.name = "say \"hi\"";
  cases.push_back({"quote", m, "contains a double quote"});
  for (const Case& c : cases) {
    for (auto write : {&write_fbx, &write_fbx_ascii}) {
      try {
        write(c.motion, dir / "out.fbx");
        ADD_FAILURE() << c.what << ": written";
      } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::kBadInput) << c.what;
        const std::string message = e.what();
        EXPECT_NE(message.find(c.message), std::string::npos) << c.what << ": " << message;
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
        EXPECT_EQ(message.find('\0'), std::string::npos) << c.what;
      }
    }
  }
  EXPECT_TRUE(std::filesystem::is_empty(dir));
  EXPECT_THROW(write_fbx(good, "/nonexistent_dir/x.fbx"), Error);
}

}  // namespace
}  // namespace wheelpose::motion
