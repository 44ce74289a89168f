#pragma once
// The two forms a motion takes inside WheelPose:
//  * PositionClip: per-frame 3D joint positions on the 23-joint skeleton (what importers produce);
//  * SkeletalMotion: rest offsets + per-frame root position and per-joint local rotations (what
//    the pipeline produces and every exporter, the body stage and the renderer consume).

#include <Eigen/Geometry>
#include <array>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "motion/skeleton.h"

namespace wheelpose::motion {

using Pose = std::array<Eigen::Vector3d, kJointCount>;
using PoseRotations = std::array<Eigen::Quaterniond, kJointCount>;

struct PositionClip {
  std::string name;          // file stem or library id; names the outputs
  std::string source;        // where it came from (path or "library:<id>")
  double fps = 20.0;
  std::vector<Pose> frames;  // metres, +Y up
  // Set by importers of sources that may be left/right mirrored (HumanML3D's HumanAct12 part);
  // the pipeline then checks handedness in "auto" mode.
  bool handedness_uncertain = false;
};

struct SkeletalMotion {
  std::string name;
  double fps = 20.0;
  // Offset of each joint from its parent in the rest pose, in the parent's frame (metres).
  // The rest pose is a T-pose facing +Z; the pelvis entry is zero.
  Pose rest_offsets{};
  std::vector<Eigen::Vector3d> root_positions;  // pelvis position per frame
  // Per frame and joint: rotation of the joint's frame relative to its parent's frame; for the
  // pelvis, relative to the world. A joint's rotation turns the bones to its children.
  std::vector<PoseRotations> local_rotations;

  std::size_t frame_count() const { return local_rotations.size(); }
};

// What a pipeline run produced for one clip: the motion, its joint positions (forward kinematics
// of the motion) and a record of where it came from and every parameter used.
struct SeatedClip {
  SkeletalMotion motion;
  std::vector<Pose> positions;
  nlohmann::ordered_json provenance;
};

// World-space joint positions of one frame.
Pose forward_kinematics(const SkeletalMotion& motion, std::size_t frame);
// World-space joint rotations of one frame (parent rotations composed down the tree).
PoseRotations global_rotations(const SkeletalMotion& motion, std::size_t frame);
std::vector<Pose> forward_kinematics(const SkeletalMotion& motion);

}  // namespace wheelpose::motion
