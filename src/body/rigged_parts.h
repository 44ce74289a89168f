#pragma once
// What every rigged-person export holds (rigged_glb.h, rigged_fbx.h), built once so that the
// glb and the FBX show the same meshes, weights and motion:
//  * the body, clothes and hair in their rest shape, skinned to the rig (the body with
//    MakeHuman's weights, a proxy vertex with its reference vertices' weights blended), at most
//    four bones per vertex, summing to 1;
//  * the wheelchair, and a walker, unskinned: the body stage keeps them still while the clip
//    turns the pelvis, so they belong to the person, not to a bone;
//  * a cane or crutch skinned rigidly to the hand bone holding it, placed as at the first frame.
// Colours are the static export's (glb_parts.h).

#include <Eigen/Geometry>
#include <optional>
#include <vector>

#include "body/glb_parts.h"
#include "body/person_animation.h"
#include "body/skin_weights.h"

namespace wheelpose::body {

struct RiggedParts {
  RiggedParts(const PersonAnimation& animation, const BodyData& data);

  SceneParts parts;
  std::vector<std::optional<SkinWeights>> skins;  // per mesh; nullopt: fixed to the person
};

// A bone's rotation relative to its parent at `pose` (RigPose rotations are global).
Eigen::Quaternionf local_rotation(const Rig& rig, const RigPose& pose, std::size_t bone);

// Where a root bone's head is at `pose`: its rest position moved by the pose's root offset.
Eigen::Vector3f root_translation(const BoneFrames& rest, const RigPose& pose, std::size_t bone);

}  // namespace wheelpose::body
