#pragma once
// Seating a motion in a wheelchair (paper "Pose Modification and Conversion" and appendix
// "Animation Clip Fix"): the pelvis keeps only its heading, the upper body keeps its world
// pose, and the legs are replaced by a seated pose — thighs raised above horizontal so the feet
// clear the footplates, shins down, feet forward — with smooth random rotational noise on
// the hip, knee and ankle of each leg.

#include <vector>

#include "core/random.h"
#include "motion/clip.h"
#include "motion/filter.h"

namespace wheelpose::motion {

struct SeatingOptions {
  double thigh_elevation_deg = 35.0;  // paper: ~35 degrees; the authors' code used 37.5
  double shin_angle_deg = 0.0;        // shin tilt from straight down, positive = feet forward
  double foot_pitch_deg = 0.0;        // 0 = feet flat, pointing forward on the footplates
  double noise_amplitude_deg = 10.0;  // U(-a, a) per axis at each noise keyframe
  double keyframe_gap_mean = 0.25;    // mean gap between noise keyframes, fraction of the clip
  double keyframe_gap_stddev = 1.0 / 32.0;  // standard deviation, fraction of the clip
  bool follow_heading = true;  // legs and root turn with the pelvis heading (wheelchair turns)
  bool keep_root_translation = false;  // seated: pelvis stays over the seat at the origin
};

// Frame indices of the noise keyframes for a clip of n frames (paper eq. 1): x0 = 0,
// x_i = x_{i-1} + k_i, k_i ~ N(gap_mean * n, (gap_stddev * n)^2), x_i < n. Gaps are rounded to
// whole frames and at least 1.
std::vector<int> noise_keyframes(int frame_count, const SeatingOptions& options,
                                 RandomStream& stream);

// Per-frame Euler angles in degrees (x, y, z) for one joint: U(-a, a) per axis at the keyframes,
// linear interpolation between them, held after the last (paper eqs. 2-4).
std::vector<Eigen::Vector3d> rotational_noise(int frame_count, const SeatingOptions& options,
                                              RandomStream& stream);

// Seats `motion` in place. Noise streams are keyed by joint name under `stream`. When `filter`
// is given, the noise angle tracks are low-passed with it (as the joint positions were).
void seat_legs(SkeletalMotion& motion, const SeatingOptions& options, const RandomStream& stream,
               const FilterCoefficients* filter);

// Seated leg directions in the heading frame (unit vectors), for tests and the body stage.
Eigen::Vector3d seated_thigh_direction(const SeatingOptions& options);
Eigen::Vector3d seated_shin_direction(const SeatingOptions& options);
Eigen::Vector3d seated_foot_direction(const SeatingOptions& options);

}  // namespace wheelpose::motion
