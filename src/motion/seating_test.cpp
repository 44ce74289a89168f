#include "motion/seating.h"

#include <gtest/gtest.h>

#include <cmath>

#include "motion/rotations.h"
#include "motion/test_support.h"

namespace wheelpose::motion {
namespace {

TEST(NoiseKeyframes, FollowThePapersGapDistribution) {
  SeatingOptions options;
  const int n = 800;
  double sum = 0, sum_sq = 0;
  int gaps = 0;
  for (int trial = 0; trial < 400; ++trial) {
    RandomStream stream(trial, {"keys"});
    auto keys = noise_keyframes(n, options, stream);
    ASSERT_EQ(keys.front(), 0);
    for (int key : keys) ASSERT_LT(key, n);
    // Only the first two gaps are always complete (x2 ~ n/2 < n); later ones are truncated at
    // the clip end, which would bias the statistics towards short gaps.
    ASSERT_GE(keys.size(), 3u);
    for (std::size_t i = 1; i < 3; ++i) {
      const double gap = keys[i] - keys[i - 1];
      sum += gap;
      sum_sq += gap * gap;
      ++gaps;
    }
  }
  const double mean = sum / gaps;
  const double stddev = std::sqrt(sum_sq / gaps - mean * mean);
  EXPECT_NEAR(mean, n / 4.0, 1.5);    // k ~ N(n/4, (n/32)^2)
  EXPECT_NEAR(stddev, n / 32.0, 2.0);
}

TEST(RotationalNoise, UniformAtKeysAndLinearBetween) {
  SeatingOptions options;
  const int n = 200;
  double sum = 0, sum_sq = 0;
  int count = 0;
  for (int trial = 0; trial < 300; ++trial) {
    RandomStream keys_stream(trial, {"noise"});
    RandomStream stream(trial, {"noise"});
    auto keys = noise_keyframes(n, options, keys_stream);
    auto track = rotational_noise(n, options, stream);
    ASSERT_EQ(track.size(), static_cast<std::size_t>(n));
    for (int key : keys) {
      for (int axis = 0; axis < 3; ++axis) {
        ASSERT_LE(std::abs(track[key][axis]), 10.0);
        sum += track[key][axis];
        sum_sq += track[key][axis] * track[key][axis];
        ++count;
      }
    }
    // Linear between the first two keys.
    const int a = keys[0], b = keys[1], mid = (a + b) / 2;
    const double t = double(mid - a) / (b - a);
    EXPECT_NEAR(track[mid].x(), track[a].x() * (1 - t) + track[b].x() * t, 1e-9);
    // Held after the last key.
    EXPECT_EQ(track.back(), track[keys.back()]);
  }
  EXPECT_NEAR(sum / count, 0.0, 0.4);
  EXPECT_NEAR(sum_sq / count, 100.0 / 3.0, 2.5);  // variance of U(-10, 10)
}

TEST(SeatLegs, NoiselessLegsTakeTheSeatedPoseAndUpperBodyKeepsItsWorldPose) {
  PositionClip clip = testing::synthetic_clip(60, 30, 5);
  SkeletalMotion motion = solve_rotations(clip.frames, clip.fps, clip.name);
  SeatingOptions options;
  options.noise_amplitude_deg = 0;
  seat_legs(motion, options, RandomStream(1, {"seat"}), nullptr);
  auto seated = forward_kinematics(motion);
  for (std::size_t f = 0; f < seated.size(); ++f) {
    const Pose& p = seated[f];
    EXPECT_LT(p[kPelvis].norm(), 1e-12);
    const Eigen::Quaterniond heading = motion.local_rotations[f][kPelvis];
    for (auto [hip, knee, ankle, toe] :
         {std::array{kLeftHip, kLeftKnee, kLeftAnkle, kLeftToe},
          std::array{kRightHip, kRightKnee, kRightAnkle, kRightToe}}) {
      const Eigen::Vector3d thigh = heading.conjugate() * (p[knee] - p[hip]).normalized();
      EXPECT_NEAR(std::asin(thigh.y()) * 180 / M_PI, 35.0, 1e-6);
      EXPECT_NEAR(thigh.x(), 0.0, 1e-9);
      EXPECT_LT(((p[ankle] - p[knee]).normalized() - Eigen::Vector3d(0, -1, 0)).norm(), 1e-9);
      const Eigen::Vector3d foot = heading.conjugate() * (p[toe] - p[ankle]).normalized();
      EXPECT_LT((foot - Eigen::Vector3d::UnitZ()).norm(), 1e-9);
    }
    // Upper body: same shape relative to the pelvis as in the source (world directions kept).
    for (int j : {kChest, kNeckBase, kHeadTop, kLeftWrist, kRightElbow}) {
      const Eigen::Vector3d source = clip.frames[f][j] - clip.frames[f][kSpine];
      const Eigen::Vector3d result = p[j] - p[kSpine];
      EXPECT_LT((source - result).norm(), 1e-9) << joint_name(j);
    }
  }
}

TEST(SeatLegs, NoiseIsBoundedSmoothAndSeeded) {
  PositionClip clip = testing::synthetic_clip(90, 30, 5);
  const SkeletalMotion solved = solve_rotations(clip.frames, clip.fps, clip.name);
  SeatingOptions options;
  auto seat = [&](std::uint64_t seed) {
    SkeletalMotion m = solved;
    seat_legs(m, options, RandomStream(seed, {"seat"}), nullptr);
    return m;
  };
  SkeletalMotion a = seat(1), b = seat(1), c = seat(2);
  double max_step = 0, max_angle = 0, differs = 0;
  for (std::size_t f = 0; f < a.frame_count(); ++f) {
    EXPECT_TRUE(a.local_rotations[f][kLeftKnee].isApprox(b.local_rotations[f][kLeftKnee], 0));
    differs += a.local_rotations[f][kLeftKnee].angularDistance(c.local_rotations[f][kLeftKnee]);
    const Eigen::Quaterniond base = Eigen::Quaterniond::FromTwoVectors(
        Eigen::Vector3d(0, -1, 0), seated_thigh_direction(options));
    max_angle = std::max(max_angle, a.local_rotations[f][kLeftHip].angularDistance(base));
    if (f > 0) {
      max_step = std::max(max_step, a.local_rotations[f][kLeftHip].angularDistance(
                                        a.local_rotations[f - 1][kLeftHip]));
    }
  }
  EXPECT_GT(differs, 0.1);
  EXPECT_LT(max_angle, 10.0 * std::sqrt(3.0) * M_PI / 180 + 1e-9);  // |U(-10,10)^3| in degrees
  EXPECT_LT(max_step, 2.0 * M_PI / 180);  // no jumps between frames
}

}  // namespace
}  // namespace wheelpose::motion
