#include "motion/seating.h"

#include <cmath>
#include <numbers>

#include "core/error.h"
#include "core/sampler.h"

namespace wheelpose::motion {

namespace {

constexpr double kDegrees = std::numbers::pi / 180.0;

// Yaw-only rotation that turns +Z to the horizontal part of `forward`.
Eigen::Quaterniond heading_of(const Eigen::Quaterniond& rotation) {
  Eigen::Vector3d forward = rotation * Eigen::Vector3d::UnitZ();
  forward.y() = 0;
  if (forward.norm() < 1e-9) return Eigen::Quaterniond::Identity();  // pelvis facing straight up
  return Eigen::Quaterniond(
      Eigen::AngleAxisd(std::atan2(forward.x(), forward.z()), Eigen::Vector3d::UnitY()));
}

struct LegJoints {
  int hip, knee, ankle;
};
constexpr LegJoints kLegs[] = {{kLeftHip, kLeftKnee, kLeftAnkle},
                               {kRightHip, kRightKnee, kRightAnkle}};

}  // namespace

Eigen::Vector3d seated_thigh_direction(const SeatingOptions& options) {
  const double a = options.thigh_elevation_deg * kDegrees;
  return {0, std::sin(a), std::cos(a)};
}

Eigen::Vector3d seated_shin_direction(const SeatingOptions& options) {
  const double a = options.shin_angle_deg * kDegrees;
  return {0, -std::cos(a), std::sin(a)};
}

Eigen::Vector3d seated_foot_direction(const SeatingOptions& options) {
  const double a = options.foot_pitch_deg * kDegrees;
  return {0, std::sin(a), std::cos(a)};
}

std::vector<int> noise_keyframes(int frame_count, const SeatingOptions& options,
                                 RandomStream& stream) {
  std::vector<int> keys = {0};
  const double mean = options.keyframe_gap_mean * frame_count;
  const double stddev = options.keyframe_gap_stddev * frame_count;
  while (true) {
    const long gap = std::max(1L, std::lround(stream.normal(mean, stddev)));
    const long next = keys.back() + gap;
    if (next >= frame_count) break;
    keys.push_back(static_cast<int>(next));
  }
  return keys;
}

std::vector<Eigen::Vector3d> rotational_noise(int frame_count, const SeatingOptions& options,
                                              RandomStream& stream) {
  const std::vector<int> keys = noise_keyframes(frame_count, options, stream);
  std::vector<Eigen::Vector3d> values;
  const double a = options.noise_amplitude_deg;
  for (std::size_t i = 0; i < keys.size(); ++i) {
    const double x = stream.uniform(-a, a);
    const double y = stream.uniform(-a, a);
    const double z = stream.uniform(-a, a);
    values.emplace_back(x, y, z);
  }
  std::vector<Eigen::Vector3d> track(frame_count);
  std::size_t segment = 0;
  for (int f = 0; f < frame_count; ++f) {
    while (segment + 1 < keys.size() && keys[segment + 1] <= f) ++segment;
    if (segment + 1 >= keys.size()) {
      track[f] = values.back();
    } else {
      const double t = static_cast<double>(f - keys[segment]) / (keys[segment + 1] - keys[segment]);
      track[f] = values[segment] * (1 - t) + values[segment + 1] * t;
    }
  }
  return track;
}

void seat_legs(SkeletalMotion& motion, const SeatingOptions& options, const RandomStream& stream,
               const FilterCoefficients* filter) {
  const int n = static_cast<int>(motion.frame_count());
  const Eigen::Vector3d down(0, -1, 0);
  const Eigen::Quaterniond thigh =
      Eigen::Quaterniond::FromTwoVectors(down, seated_thigh_direction(options));
  const Eigen::Quaterniond shin =
      Eigen::Quaterniond::FromTwoVectors(down, seated_shin_direction(options));
  const Eigen::Quaterniond foot = Eigen::Quaterniond::FromTwoVectors(
      Eigen::Vector3d::UnitZ(), seated_foot_direction(options));

  // One smooth noise track per leg joint, each from its own stream.
  std::array<std::vector<Eigen::Quaterniond>, kJointCount> noise;
  for (const LegJoints& leg : kLegs) {
    for (int joint : {leg.hip, leg.knee, leg.ankle}) {
      RandomStream joint_stream = stream.child({"leg_noise", joint_name(joint)});
      std::vector<Eigen::Vector3d> angles = rotational_noise(n, options, joint_stream);
      if (filter && n > filtfilt_padding(*filter)) {
        std::vector<double> axis_track(n);
        for (int axis = 0; axis < 3; ++axis) {
          for (int f = 0; f < n; ++f) axis_track[f] = angles[f][axis];
          axis_track = filtfilt(*filter, axis_track);
          for (int f = 0; f < n; ++f) angles[f][axis] = axis_track[f];
        }
      }
      noise[joint].resize(n);
      for (int f = 0; f < n; ++f) noise[joint][f] = euler_xyz_extrinsic(angles[f] * kDegrees);
    }
  }

  for (int f = 0; f < n; ++f) {
    PoseRotations& local = motion.local_rotations[f];
    const Eigen::Quaterniond pelvis = local[kPelvis];
    const Eigen::Quaterniond heading =
        options.follow_heading ? heading_of(pelvis) : Eigen::Quaterniond::Identity();
    // The spine absorbs the pelvis tilt so the upper body keeps its world pose.
    local[kSpine] = (heading.conjugate() * pelvis * local[kSpine]).normalized();
    local[kPelvis] = heading;
    for (const LegJoints& leg : kLegs) {
      local[leg.hip] = (thigh * noise[leg.hip][f]).normalized();
      local[leg.knee] = (thigh.conjugate() * shin * noise[leg.knee][f]).normalized();
      local[leg.ankle] = (shin.conjugate() * foot * noise[leg.ankle][f]).normalized();
    }
    local[kLeftToe] = local[kRightToe] = Eigen::Quaterniond::Identity();
    if (!options.keep_root_translation) motion.root_positions[f] = Eigen::Vector3d::Zero();
  }
}

}  // namespace wheelpose::motion
