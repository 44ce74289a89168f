#include "motion/skeleton.h"

#include "core/error.h"

namespace wheelpose::motion {

namespace {

struct JointInfo {
  std::string_view name;
  int parent;
  int mirror;
  Eigen::Vector3d rest_direction;
  double default_length;
};

const std::array<JointInfo, kJointCount>& joint_table() {
  using V = Eigen::Vector3d;
  static const std::array<JointInfo, kJointCount> table = {{
      {"pelvis", -1, kPelvis, V(0, 0, 0), 0.0},
      {"left_hip", kPelvis, kRightHip, V(1, 0, 0), 0.10},
      {"right_hip", kPelvis, kLeftHip, V(-1, 0, 0), 0.10},
      {"spine", kPelvis, kSpine, V(0, 1, 0), 0.11},
      {"left_knee", kLeftHip, kRightKnee, V(0, -1, 0), 0.40},
      {"right_knee", kRightHip, kLeftKnee, V(0, -1, 0), 0.40},
      {"chest", kSpine, kChest, V(0, 1, 0), 0.13},
      {"left_ankle", kLeftKnee, kRightAnkle, V(0, -1, 0), 0.41},
      {"right_ankle", kRightKnee, kLeftAnkle, V(0, -1, 0), 0.41},
      {"upper_chest", kChest, kUpperChest, V(0, 1, 0), 0.06},
      {"left_toe", kLeftAnkle, kRightToe, V(0, 0, 1), 0.14},
      {"right_toe", kRightAnkle, kLeftToe, V(0, 0, 1), 0.14},
      {"head_base", kNeckBase, kHeadBase, V(0, 1, 0), 0.07},
      {"left_clavicle", kNeckBase, kRightClavicle, V(1, 0, 0), 0.03},
      {"right_clavicle", kNeckBase, kLeftClavicle, V(-1, 0, 0), 0.03},
      {"head_top", kHeadBase, kHeadTop, V(0, 1, 0), 0.20},
      {"left_shoulder", kLeftClavicle, kRightShoulder, V(1, 0, 0), 0.12},
      {"right_shoulder", kRightClavicle, kLeftShoulder, V(-1, 0, 0), 0.12},
      {"left_elbow", kLeftShoulder, kRightElbow, V(1, 0, 0), 0.27},
      {"right_elbow", kRightShoulder, kLeftElbow, V(-1, 0, 0), 0.27},
      {"left_wrist", kLeftElbow, kRightWrist, V(1, 0, 0), 0.25},
      {"right_wrist", kRightElbow, kLeftWrist, V(-1, 0, 0), 0.25},
      {"neck_base", kUpperChest, kNeckBase, V(0, 1, 0), 0.15},
  }};
  return table;
}

const JointInfo& info(int joint) {
  WHEELPOSE_CHECK(joint >= 0 && joint < kJointCount);
  return joint_table()[joint];
}

}  // namespace

std::string_view joint_name(int joint) { return info(joint).name; }

std::optional<int> joint_from_name(std::string_view name) {
  for (int j = 0; j < kJointCount; ++j) {
    if (joint_table()[j].name == name) return j;
  }
  return std::nullopt;
}

int joint_parent(int joint) { return info(joint).parent; }

int mirror_joint(int joint) { return info(joint).mirror; }

Eigen::Vector3d rest_direction(int joint) { return info(joint).rest_direction; }

double default_bone_length(int joint) { return info(joint).default_length; }

const std::array<int, kJointCount>& joints_parent_first() {
  static const std::array<int, kJointCount> order = [] {
    std::array<int, kJointCount> result{};
    std::array<bool, kJointCount> placed{};
    int count = 0;
    while (count < kJointCount) {
      for (int j = 0; j < kJointCount; ++j) {
        if (placed[j]) continue;
        int parent = joint_table()[j].parent;
        if (parent < 0 || placed[parent]) {
          result[count++] = j;
          placed[j] = true;
        }
      }
    }
    return result;
  }();
  return order;
}

bool is_leg_joint(int joint) {
  switch (joint) {
    case kLeftHip:
    case kRightHip:
    case kLeftKnee:
    case kRightKnee:
    case kLeftAnkle:
    case kRightAnkle:
    case kLeftToe:
    case kRightToe:
      return true;
    default:
      return false;
  }
}

}  // namespace wheelpose::motion
