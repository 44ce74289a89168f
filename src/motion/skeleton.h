#pragma once
// The 23-joint WheelPose skeleton (paper "Human Skeletal Modeling"; joint set of the authors'
// code with its left/right naming mistakes corrected). Frame convention: metres, +Y up, the body
// faces +Z, so the subject's left is +X.

#include <Eigen/Core>
#include <array>
#include <optional>
#include <string_view>

namespace wheelpose::motion {

enum Joint : int {
  kPelvis = 0,
  kLeftHip = 1,
  kRightHip = 2,
  kSpine = 3,
  kLeftKnee = 4,
  kRightKnee = 5,
  kChest = 6,
  kLeftAnkle = 7,
  kRightAnkle = 8,
  kUpperChest = 9,
  kLeftToe = 10,
  kRightToe = 11,
  kHeadBase = 12,
  kLeftClavicle = 13,
  kRightClavicle = 14,
  kHeadTop = 15,
  kLeftShoulder = 16,
  kRightShoulder = 17,
  kLeftElbow = 18,
  kRightElbow = 19,
  kLeftWrist = 20,
  kRightWrist = 21,
  kNeckBase = 22,
};

inline constexpr int kJointCount = 23;

// Snake-case names used in every file format we write ("left_hip", "neck_base", ...).
std::string_view joint_name(int joint);
std::optional<int> joint_from_name(std::string_view name);

// Parent joint, -1 for the pelvis (root).
int joint_parent(int joint);

// Joints ordered so that every parent precedes its children (pelvis first).
const std::array<int, kJointCount>& joints_parent_first();

// The mirror-image joint (left <-> right); centre joints map to themselves.
int mirror_joint(int joint);

// Direction of the bone parent->joint in the rest pose: a T-pose, arms out sideways, legs down,
// feet forward. Zero for the pelvis.
Eigen::Vector3d rest_direction(int joint);

// Joints whose rotation moves the legs (hips, knees, ankles) and the leg joints themselves.
bool is_leg_joint(int joint);

// A plausible adult's bone lengths (metres), used where a source gives no lengths
// (the built-in motion library) — indexed by child joint, zero for the pelvis.
double default_bone_length(int joint);

}  // namespace wheelpose::motion
