#pragma once
// Header-only helpers for motion tests: a smooth synthetic clip with known rotations.

#include <cmath>

#include "core/random.h"
#include "motion/clip.h"

namespace wheelpose::motion::testing {

inline Pose default_rest_offsets() {
  Pose offsets;
  for (int j = 0; j < kJointCount; ++j) offsets[j] = rest_direction(j) * default_bone_length(j);
  return offsets;
}

// A motion whose every joint turns smoothly (sinusoids about random axes, up to `amplitude`
// radians) and whose root walks and turns.
inline SkeletalMotion synthetic_motion(int frames, double fps, std::uint64_t seed,
                                       double amplitude = 0.6) {
  SkeletalMotion motion;
  motion.name = "synthetic";
  motion.fps = fps;
  motion.rest_offsets = default_rest_offsets();
  RandomStream stream(seed, {"synthetic_motion"});
  std::array<Eigen::Vector3d, kJointCount> axes;
  std::array<double, kJointCount> frequency, phase;
  for (int j = 0; j < kJointCount; ++j) {
    axes[j] = Eigen::Vector3d(stream.normal(0, 1), stream.normal(0, 1), stream.normal(0, 1))
                  .normalized();
    frequency[j] = stream.uniform(0.2, 1.5);
    phase[j] = stream.uniform(0, 6.28);
  }
  for (int f = 0; f < frames; ++f) {
    const double t = f / fps;
    PoseRotations local;
    for (int j = 0; j < kJointCount; ++j) {
      const double angle = amplitude * std::sin(2 * M_PI * frequency[j] * t + phase[j]);
      local[j] = Eigen::Quaterniond(Eigen::AngleAxisd(angle, axes[j]));
    }
    local[kPelvis] = Eigen::AngleAxisd(0.4 * t, Eigen::Vector3d::UnitY()) *
                     Eigen::AngleAxisd(0.2 * std::sin(t), Eigen::Vector3d::UnitX());
    motion.local_rotations.push_back(local);
    motion.root_positions.emplace_back(0.3 * t, 0.9 + 0.02 * std::sin(3 * t), 0.1 * t);
  }
  return motion;
}

inline PositionClip synthetic_clip(int frames, double fps, std::uint64_t seed,
                                   double amplitude = 0.6) {
  PositionClip clip;
  clip.name = "synthetic";
  clip.source = "synthetic.npy";
  clip.fps = fps;
  clip.frames = forward_kinematics(synthetic_motion(frames, fps, seed, amplitude));
  return clip;
}

inline double max_joint_error(const std::vector<Pose>& a, const std::vector<Pose>& b,
                              bool upper_body_only = false) {
  double worst = 0;
  for (std::size_t f = 0; f < a.size(); ++f) {
    for (int j = 0; j < kJointCount; ++j) {
      if (upper_body_only && (is_leg_joint(j) || j == kPelvis)) continue;
      worst = std::max(worst, (a[f][j] - b[f][j]).norm());
    }
  }
  return worst;
}

}  // namespace wheelpose::motion::testing
