#include "body/limb.h"

#include <map>
#include <set>

#include "core/error.h"
#include "motion/skeleton.h"

namespace wheelpose::body {

namespace {

struct LimbInfo {
  const char* name;
  const char* upper_bone;   // thigh / upperarm
  const char* lower_bone;   // calf / lowerarm
  const char* joint_word;   // knee / elbow
  int middle_joint;         // knee / elbow (absent when cut above)
  std::vector<int> beyond;  // joints absent when cut below
};

const LimbInfo& info(Limb limb) {
  static const std::array<LimbInfo, 4> table = {{
      {"left_leg",
       "thigh_l",
       "calf_l",
       "knee",
       motion::kLeftKnee,
       {motion::kLeftAnkle, motion::kLeftToe}},
      {"right_leg",
       "thigh_r",
       "calf_r",
       "knee",
       motion::kRightKnee,
       {motion::kRightAnkle, motion::kRightToe}},
      {"left_arm", "upperarm_l", "lowerarm_l", "elbow", motion::kLeftElbow, {motion::kLeftWrist}},
      {"right_arm",
       "upperarm_r",
       "lowerarm_r",
       "elbow",
       motion::kRightElbow,
       {motion::kRightWrist}},
  }};
  return table[static_cast<int>(limb)];
}

// Bones below a bone in the rig tree, itself included.
std::set<int> subtree(const Rig& rig, int root) {
  std::set<int> out = {root};
  for (std::size_t b = 0; b < rig.bones.size(); ++b) {
    if (rig.bones[b].parent >= 0 && out.count(rig.bones[b].parent)) out.insert(static_cast<int>(b));
  }
  return out;
}

}  // namespace

const char* limb_name(Limb limb) { return info(limb).name; }

Limb limb_from_name(const std::string& name) {
  for (int i = 0; i < 4; ++i) {
    if (name == info(static_cast<Limb>(i)).name) return static_cast<Limb>(i);
  }
  throw Error("limb '" + name + "': expected left_leg, right_leg, left_arm or right_arm");
}

std::string cut_name(Limb limb, Cut cut) {
  if (cut == Cut::kNone) return "none";
  return std::string(cut == Cut::kBelow ? "below_" : "above_") + info(limb).joint_word;
}

Cut cut_from_name(Limb limb, const std::string& value) {
  for (Cut c : {Cut::kNone, Cut::kBelow, Cut::kAbove}) {
    if (value == cut_name(limb, c)) return c;
  }
  throw Error(std::string(limb_name(limb)) + "=" + value + ": expected none, below_" +
              info(limb).joint_word + " or above_" + info(limb).joint_word);
}

std::vector<int> absent_joints(const LimbCuts& cuts) {
  std::vector<int> out;
  for (int i = 0; i < 4; ++i) {
    if (cuts[i] == Cut::kNone) continue;
    const LimbInfo& l = info(static_cast<Limb>(i));
    if (cuts[i] == Cut::kAbove) out.push_back(l.middle_joint);
    out.insert(out.end(), l.beyond.begin(), l.beyond.end());
  }
  return out;
}

std::vector<int> limbs_beyond_cuts(const Rig& rig, const BoneFrames& bones,
                                   const std::vector<Eigen::Vector3f>& rest,
                                   const std::vector<int>& vertex_ids, const LimbCuts& cuts) {
  std::vector<int> limb_of(rest.size(), -1);
  for (int i = 0; i < 4; ++i) {
    if (cuts[i] == Cut::kNone) continue;
    const LimbInfo& l = info(static_cast<Limb>(i));
    // Cut plane across the bone: 40% down the shin/forearm or 55% down the thigh/upper arm.
    const int bone = rig.bone(cuts[i] == Cut::kBelow ? l.lower_bone : l.upper_bone);
    const float at = cuts[i] == Cut::kBelow ? 0.4f : 0.55f;
    const Eigen::Vector3f head = bones.head[bone], axis = bones.tail[bone] - bones.head[bone];
    const Eigen::Vector3f plane = head + at * axis, normal = axis.normalized();
    const std::set<int> limb_bones = subtree(rig, rig.bone(l.upper_bone));
    for (std::size_t v = 0; v < rest.size(); ++v) {
      // Only vertices skinned mostly to this limb, beyond the plane.
      const int dominant = rig.influence_bone[vertex_ids[v]][0];
      if (limb_bones.count(dominant) && (rest[v] - plane).dot(normal) > 0) limb_of[v] = i;
    }
  }
  return limb_of;
}

CutResult cut_limbs(const Rig& rig, const BoneFrames& bones,
                    const std::vector<Eigen::Vector3f>& rest, const std::vector<int>& vertex_ids,
                    const std::vector<std::array<unsigned, 3>>& triangles, const LimbCuts& cuts) {
  CutResult result;
  const std::vector<int> limb_of = limbs_beyond_cuts(rig, bones, rest, vertex_ids, cuts);
  result.removed.resize(rest.size());
  for (std::size_t v = 0; v < rest.size(); ++v) result.removed[v] = limb_of[v] >= 0;
  // Keep triangles with no removed vertex; edges they share with dropped triangles form the rims.
  std::map<std::pair<unsigned, unsigned>, int>
      rim_edges;  // directed edge of a kept triangle -> limb
  std::vector<std::array<unsigned, 3>> dropped;
  for (const auto& t : triangles) {
    if (result.removed[t[0]] || result.removed[t[1]] || result.removed[t[2]]) {
      dropped.push_back(t);
    } else {
      result.triangles.push_back(t);
    }
  }
  std::map<std::pair<unsigned, unsigned>, int> dropped_edges;
  for (const auto& t : dropped) {
    int limb = -1;
    for (unsigned v : t) limb = std::max(limb, limb_of[v]);
    for (int k = 0; k < 3; ++k) dropped_edges[{t[(k + 1) % 3], t[k]}] = limb;  // reversed
  }
  for (const auto& t : result.triangles) {
    for (int k = 0; k < 3; ++k) {
      const auto it = dropped_edges.find({t[k], t[(k + 1) % 3]});
      if (it != dropped_edges.end() && it->second >= 0)
        rim_edges[{t[k], t[(k + 1) % 3]}] = it->second;
    }
  }
  // One fan per limb: the cap centre is a new vertex (index rest.size() + n), placed by the
  // caller at the mean of its rim.
  std::map<int, unsigned> centre_of;
  for (const auto& [edge, limb] : rim_edges) {
    if (!centre_of.count(limb)) {
      centre_of[limb] = static_cast<unsigned>(rest.size() + result.caps.size());
      result.caps.push_back(centre_of[limb]);
      result.cap_rims.emplace_back();
    }
    const unsigned centre = centre_of[limb];
    auto& rim = result.cap_rims[centre - rest.size()];
    rim.push_back(edge.first);
    // Reverse the kept triangle's edge so the cap faces outward.
    result.triangles.push_back({edge.second, edge.first, centre});
  }
  return result;
}

}  // namespace wheelpose::body
