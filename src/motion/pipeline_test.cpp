#include "motion/pipeline.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "core/error.h"
#include "motion/clip_json.h"
#include "motion/library.h"
#include "motion/plausibility.h"
#include "motion/test_support.h"

namespace wheelpose::motion {
namespace {

std::string error_of(const PositionClip& clip) {
  try {
    run_motion_pipeline(clip, MotionOptions{});
  } catch (const Error& e) {
    return e.what();
  }
  return "<no error>";
}

TEST(MotionPipeline, ProducesASeatedClipFacingPlusZ) {
  PositionClip clip = testing::synthetic_clip(80, 20, 3);
  SeatedClip seated = run_motion_pipeline(clip, MotionOptions{});
  ASSERT_EQ(seated.positions.size(), 80u);
  EXPECT_EQ(seated.motion.fps, 20);
  EXPECT_LT(testing::max_joint_error(forward_kinematics(seated.motion), seated.positions), 1e-12);
  // First frame: pelvis at the origin, hips facing +Z, knees above the hips (raised thighs).
  const Pose& first = seated.positions.front();
  EXPECT_LT(first[kPelvis].norm(), 1e-12);
  EXPECT_GT(hip_facing(first).z(), 0.999);
  for (const Pose& p : seated.positions) {
    EXPECT_GT(p[kLeftKnee].y(), p[kLeftHip].y());
    EXPECT_GT(p[kHeadTop].y(), p[kPelvis].y());
  }
  EXPECT_EQ(seated.provenance["source"], "synthetic.npy");
  EXPECT_EQ(seated.provenance["filter"], "applied");
}

TEST(MotionPipeline, SameSeedSameBytesOtherSeedOtherLegs) {
  PositionClip clip = testing::synthetic_clip(60, 20, 3);
  MotionOptions options;
  options.seed = 9;
  const std::string a = seated_clip_json_text(run_motion_pipeline(clip, options));
  const std::string b = seated_clip_json_text(run_motion_pipeline(clip, options));
  options.seed = 10;
  const std::string c = seated_clip_json_text(run_motion_pipeline(clip, options));
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
}

TEST(MotionPipeline, NormalizesYawAndUndoesMirroring) {
  PositionClip clip = testing::synthetic_clip(40, 20, 4);
  // Give the head a forward lean like SMPL's head joint, turn the body, then mirror it.
  const Eigen::AngleAxisd turn(1.2, Eigen::Vector3d::UnitY());
  for (Pose& pose : clip.frames) {
    pose[kHeadTop] += 0.08 * hip_facing(pose);
    for (Eigen::Vector3d& p : pose) p = turn * p;
  }
  std::vector<Pose> plain = clip.frames;
  EXPECT_FALSE(looks_mirrored(plain));
  auto result = normalize_orientation(plain, Handedness::kAuto);
  EXPECT_FALSE(result.mirrored);
  EXPECT_GT(hip_facing(plain.front()).z(), 0.999);

  std::vector<Pose> mirrored = clip.frames;
  for (Pose& pose : mirrored) {
    for (Eigen::Vector3d& p : pose) p.x() = -p.x();
  }
  EXPECT_TRUE(looks_mirrored(mirrored));
  result = normalize_orientation(mirrored, Handedness::kAuto);
  EXPECT_TRUE(result.mirrored);
  EXPECT_GT(hip_facing(mirrored.front()).z(), 0.999);
  // Un-mirroring restores the original shape: same joint distances as the plain clip.
  for (int j = 0; j < kJointCount; ++j) {
    EXPECT_NEAR((mirrored[5][j] - mirrored[5][kPelvis]).norm(),
                (plain[5][j] - plain[5][kPelvis]).norm(), 1e-9);
  }
}

TEST(MotionPipeline, RejectsBrokenClipsNamingTheReason) {
  PositionClip clip = testing::synthetic_clip(40, 20, 4);
  PositionClip nan = clip;
  nan.frames[7][kLeftElbow].x() = std::nan("");
  EXPECT_EQ(error_of(nan), "synthetic.npy: frame 7 joint left_elbow is not a finite number");
  PositionClip short_clip = clip;
  short_clip.frames.resize(12);
  EXPECT_EQ(error_of(short_clip),
            "synthetic.npy: has 12 frames; at least 13 are needed (filter padding)");
  PositionClip collapsed = clip;
  for (Pose& pose : collapsed.frames) pose[kLeftWrist] = pose[kLeftElbow];
  EXPECT_EQ(error_of(collapsed).rfind("synthetic.npy: bone left_elbow->left_wrist is collapsed", 0),
            0u);
  PositionClip exploding = clip;
  exploding.frames[20][kRightWrist] += Eigen::Vector3d(0, 3, 0);
  EXPECT_EQ(error_of(exploding).rfind("synthetic.npy: bone right_elbow->right_wrist explodes", 0),
            0u);
}

TEST(MotionPipeline, SkipsTheFilterBelowTwiceTheCutoff) {
  PositionClip clip = testing::synthetic_clip(40, 8, 4);
  SeatedClip seated = run_motion_pipeline(clip, MotionOptions{});
  EXPECT_EQ(seated.provenance["filter"], "skipped: cutoff is at or above the Nyquist frequency");
}

TEST(MotionOptions, ReadsConfigAndRejectsUnknownKeys) {
  auto root = ConfigNode::load_string(
      "motion:\n  filter: {cutoff_hz: 4}\n  seat:\n    thigh_elevation_deg: 37.5\n  seed: 3\n",
      "m.yaml");
  MotionOptions o = MotionOptions::from_config(root.child("motion"));
  EXPECT_EQ(o.filter_cutoff_hz, 4);
  EXPECT_EQ(o.seating.thigh_elevation_deg, 37.5);
  EXPECT_EQ(o.seed, 3u);
  auto bad = ConfigNode::load_string("motion:\n  seat:\n    thigh_angle: 3\n", "m.yaml");
  try {
    MotionOptions::from_config(bad.child("motion"));
    FAIL();
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "m.yaml:3: key 'motion.seat.thigh_angle': unknown key");
  }
}

TEST(MotionOptions, ShippedConfigStatesExactlyTheDefaults) {
  auto root = ConfigNode::load_file(std::string(WHEELPOSE_SOURCE_DIR) + "/configs/motion.yaml");
  MotionOptions shipped = MotionOptions::from_config(root.child("motion"));
  root.finish();
  EXPECT_EQ(shipped.to_json(), MotionOptions{}.to_json());
}

TEST(SeatedClipJson, RoundTripsWithinRounding) {
  SeatedClip seated = run_motion_pipeline(testing::synthetic_clip(30, 20, 2), MotionOptions{});
  auto path = std::filesystem::temp_directory_path() / "wheelpose_clip_roundtrip.json";
  write_seated_clip_json(seated, path);
  SeatedClip back = read_seated_clip_json(path);
  ASSERT_EQ(back.positions.size(), seated.positions.size());
  EXPECT_EQ(back.motion.name, seated.motion.name);
  EXPECT_LT(testing::max_joint_error(back.positions, seated.positions), 1e-6);
  // The stored rotations still reproduce the stored positions.
  EXPECT_LT(testing::max_joint_error(forward_kinematics(back.motion), back.positions), 1e-5);
  EXPECT_EQ(seated_clip_json_text(back), seated_clip_json_text(seated));
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace wheelpose::motion

namespace wheelpose::motion {
namespace {

TEST(MotionPipeline, EverySeatedLibraryClipIsPlausible) {
  // Seating (new legs, heading-only pelvis, filtering) must not push the built-in motions out
  // of human joint ranges or through the body.
  for (std::uint64_t seed : {1u, 2u}) {
    MotionOptions options;
    options.seed = seed;
    for (const PositionClip& clip : library_clips(seed)) {
      const SeatedClip seated = run_motion_pipeline(clip, options);
      const auto problems = plausibility_problems(seated.positions);
      EXPECT_TRUE(problems.empty()) << clip.name << " seed " << seed << ": " << problems.front();
    }
  }
}

}  // namespace
}  // namespace wheelpose::motion

namespace wheelpose::motion {
namespace {

TEST(MotionOptions, CheckHoldsTheRangesTheConfigReaderEnforces) {
  EXPECT_NO_THROW(MotionOptions{}.check());
  auto rejects = [](auto change, const char* name) {
    MotionOptions o;
    change(o);
    try {
      o.check();
      ADD_FAILURE() << name << " accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), ErrorKind::kBadInput);
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
  };
  rejects([](MotionOptions& o) { o.filter_order = 9; }, "filter.order");
  rejects([](MotionOptions& o) { o.filter_cutoff_hz = std::nan(""); }, "filter.cutoff_hz");
  rejects([](MotionOptions& o) { o.seating.noise_amplitude_deg = -1; }, "seat.noise_amplitude_deg");
  rejects([](MotionOptions& o) { o.seating.keyframe_gap_mean = 0; }, "seat.keyframe_gap_mean");
  rejects([](MotionOptions& o) { o.limits.max_bone_length = 0; }, "limits.max_bone_length");
  // The pipeline refuses such options before touching the clip.
  MotionOptions bad;
  bad.filter_order = 0;
  EXPECT_THROW(run_motion_pipeline(PositionClip{}, bad), Error);
}

}  // namespace
}  // namespace wheelpose::motion
