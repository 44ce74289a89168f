#pragma once
// Limb difference (asked for by amputee participants in the paper): a leg removed below or above
// the knee, an arm below or above the elbow, on either side. The body mesh is cut along the
// bone, the opening capped with a fan, and the joints beyond the cut reported absent.

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "body/rig.h"

namespace wheelpose::body {

enum class Limb { kLeftLeg = 0, kRightLeg = 1, kLeftArm = 2, kRightArm = 3 };
enum class Cut { kNone = 0, kBelow = 1, kAbove = 2 };  // below/above the knee or elbow
using LimbCuts = std::array<Cut, 4>;

// "left_leg", "right_arm", ... and "below_knee", "above_knee", "below_elbow", "above_elbow",
// "none"; throws Error naming the value.
Limb limb_from_name(const std::string& name);
Cut cut_from_name(Limb limb, const std::string& value);
const char* limb_name(Limb limb);
std::string cut_name(Limb limb, Cut cut);

// Our joints (motion::Joint) beyond the cuts.
std::vector<int> absent_joints(const LimbCuts& cuts);

// Per vertex (rest pose, `vertex_ids` = base-mesh ids for the skin weights): the limb (Limb
// index) whose cut removes it, or -1. A vertex goes when it is skinned mostly to the limb and lies
// beyond the cut plane across the bone (40 % down the shin/forearm, 55 % down the thigh/arm).
std::vector<int> limbs_beyond_cuts(const Rig& rig, const BoneFrames& bones,
                                   const std::vector<Eigen::Vector3f>& rest,
                                   const std::vector<int>& vertex_ids, const LimbCuts& cuts);

// Removes the cut parts from a triangle mesh over body vertices `rest` (rest pose, with rig
// bones `bones`; `vertex_ids` maps mesh vertex -> base-mesh vertex for the skin weights) and
// caps each opening. Returns the new triangles; cap centres are appended to `rest_out` as new
// vertices (their base-mesh id in `cap_anchor`: the vertex they move with).
struct CutResult {
  std::vector<std::array<unsigned, 3>> triangles;
  std::vector<bool> removed;                    // per original mesh vertex
  std::vector<unsigned> caps;                   // indices of the appended cap-centre vertices
  std::vector<std::vector<unsigned>> cap_rims;  // rim vertices of each cap (for its position)
};
CutResult cut_limbs(const Rig& rig, const BoneFrames& bones,
                    const std::vector<Eigen::Vector3f>& rest, const std::vector<int>& vertex_ids,
                    const std::vector<std::array<unsigned, 3>>& triangles, const LimbCuts& cuts);

}  // namespace wheelpose::body
