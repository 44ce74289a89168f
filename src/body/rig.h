#pragma once
// The skeleton used to pose bodies: MPFB2's "game_engine" rig (53 bones, Unreal-style names:
// pelvis, spine_01..03, neck_01, head, clavicle/upperarm/lowerarm/hand, thigh/calf/foot/ball,
// fingers). Chosen over the 163-bone default rig because it has every bone our 23-joint skeleton
// needs, weights for every body vertex, and is small enough to skin in well under a millisecond.
// Bone heads and tails are recomputed from the morphed mesh: "CUBE" = mean of the vertices of
// the base mesh's joint-<name> helper group, "MEAN" = mean of listed vertices.

#include <Eigen/Geometry>
#include <filesystem>
#include <string>
#include <vector>

#include "motion/clip.h"

namespace wheelpose::body {

struct JointRef {
  std::vector<int> vertices;  // mean of these morphed vertices
};

struct RigBone {
  std::string name;
  int parent = -1;  // index into Rig::bones, parents precede children
  JointRef head, tail;
};

struct Rig {
  std::vector<RigBone> bones;
  // Per body vertex (all base-mesh vertices): up to kMaxInfluences (bone, weight), normalised.
  static constexpr int kMaxInfluences = 4;
  std::vector<std::array<int, kMaxInfluences>> influence_bone;
  std::vector<std::array<float, kMaxInfluences>> influence_weight;

  int bone(const std::string& name) const;  // -1 if absent
};

// Reads rigs/rig.game_engine.json and rigs/weights.game_engine.json under `makehuman_root`,
// resolving CUBE joints against the base mesh's groups.
struct BaseMesh;
Rig load_rig(const std::filesystem::path& makehuman_root, const BaseMesh& base);

struct BoneFrames {
  std::vector<Eigen::Vector3f> head, tail;  // metres
};
BoneFrames bone_positions(const Rig& rig, const std::vector<Eigen::Vector3f>& vertices);

// A pose: global rotation of each bone (relative to its rest orientation) and root translation.
struct RigPose {
  std::vector<Eigen::Quaternionf> rotation;  // per bone
  Eigen::Vector3f root_offset = Eigen::Vector3f::Zero();
};
RigPose bind_pose(const Rig& rig);

// Posed bone heads/tails by forward kinematics from the rest bones.
BoneFrames pose_bones(const Rig& rig, const BoneFrames& rest, const RigPose& pose);

// Linear blend skinning of `vertices` (rest, metres).
std::vector<Eigen::Vector3f> skin(const Rig& rig, const BoneFrames& rest, const RigPose& pose,
                                  const std::vector<Eigen::Vector3f>& vertices);

// Rig bone driven by each of our skeleton's bones: the clip bone runs from joint
// `clip_parent` to `clip_child` and drives rig bone `rig_bone` (head->tail).
struct BoneMapping {
  const char* rig_bone;
  int clip_parent;
  int clip_child;
};
const std::vector<BoneMapping>& bone_mapping();

// Poses the rig so that every mapped rig bone points along its clip bone, with the clip joint's
// twist; unmapped bones (fingers, toes) keep their rest pose relative to their parent.
// `global` = clip global joint rotations (motion::global_rotations).
RigPose retarget(const Rig& rig, const BoneFrames& rest, const motion::PoseRotations& global);

// Rig joint standing for each of our 23 joints on the posed body (metres).
motion::Pose skeleton_joints(const Rig& rig, const BoneFrames& posed);

}  // namespace wheelpose::body
