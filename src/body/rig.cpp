#include "body/rig.h"

#include <algorithm>
#include <map>
#include <nlohmann/json.hpp>

#include "body/assets.h"
#include "body/human.h"
#include "core/error.h"

namespace wheelpose::body {

namespace fs = std::filesystem;
using motion::Joint;

int Rig::bone(const std::string& name) const {
  for (std::size_t i = 0; i < bones.size(); ++i) {
    if (bones[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

namespace {

JointRef parse_joint(const nlohmann::json& j, const BaseMesh& base, const std::string& where) {
  const std::string strategy = j.value("strategy", "");
  JointRef ref;
  if (strategy == "CUBE") {
    const std::string cube = j.value("cube_name", "");
    const auto it = base.group_vertices.find(cube);
    if (it == base.group_vertices.end()) {
      throw Error(where + ": joint cube '" + cube + "' is not a group of base.obj");
    }
    ref.vertices = it->second;
  } else if (strategy == "MEAN" || strategy == "VERTEX") {
    for (const auto& v : j.at("vertex_indices")) ref.vertices.push_back(v.get<int>());
  } else {
    throw Error(where + ": unknown joint strategy '" + strategy + "'");
  }
  for (int v : ref.vertices) {
    if (v < 0 || v >= static_cast<int>(base.vertices.size())) {
      throw Error(where + ": vertex index " + std::to_string(v) + " out of range");
    }
  }
  if (ref.vertices.empty()) throw Error(where + ": joint has no vertices");
  return ref;
}

Eigen::Vector3f mean_of(const JointRef& ref, const std::vector<Eigen::Vector3f>& v) {
  Eigen::Vector3f sum = Eigen::Vector3f::Zero();
  for (int i : ref.vertices) sum += v[i];
  return sum / static_cast<float>(ref.vertices.size());
}

}  // namespace

Rig load_rig(const fs::path& root, const BaseMesh& base) {
  const fs::path rig_path = root / "rigs" / "rig.game_engine.json";
  const fs::path weights_path = root / "rigs" / "weights.game_engine.json";
  const auto rig_json = nlohmann::json::parse(read_asset(rig_path), nullptr, false);
  if (rig_json.is_discarded() || !rig_json.is_object()) {
    throw Error(rig_path.string() + ": not valid JSON; run scripts/setup.sh");
  }
  // Order bones parents-first (the file is alphabetical).
  Rig rig;
  std::map<std::string, int> index;
  std::vector<std::string> pending;
  for (const auto& [name, bone] : rig_json.items()) pending.push_back(name);
  while (!pending.empty()) {
    std::vector<std::string> next;
    for (const std::string& name : pending) {
      const auto& bone = rig_json[name];
      const std::string parent = bone.value("parent", "");
      if (!parent.empty() && !index.count(parent)) {
        if (!rig_json.contains(parent)) {
          throw Error(rig_path.string() + ": bone " + name + ": unknown parent " + parent);
        }
        next.push_back(name);
        continue;
      }
      RigBone b;
      b.name = name;
      b.parent = parent.empty() ? -1 : index[parent];
      try {
        b.head = parse_joint(bone.at("head"), base, rig_path.string() + ": " + name + ".head");
        b.tail = parse_joint(bone.at("tail"), base, rig_path.string() + ": " + name + ".tail");
      } catch (const nlohmann::json::exception& e) {
        throw Error(rig_path.string() + ": bone " + name + ": " + e.what());
      }
      index[name] = static_cast<int>(rig.bones.size());
      rig.bones.push_back(std::move(b));
    }
    if (next.size() == pending.size())
      throw Error(rig_path.string() + ": bone parents form a cycle");
    pending = std::move(next);
  }
  for (const BoneMapping& m : bone_mapping()) {
    if (rig.bone(m.rig_bone) < 0) {
      throw Error(rig_path.string() + ": bone '" + m.rig_bone + "' missing");
    }
  }

  const auto weights_json = nlohmann::json::parse(read_asset(weights_path), nullptr, false);
  if (weights_json.is_discarded() || !weights_json.contains("weights")) {
    throw Error(weights_path.string() + ": no 'weights' object; run scripts/setup.sh");
  }
  const std::size_t n = base.vertices.size();
  std::vector<std::vector<std::pair<float, int>>> per_vertex(n);
  for (const auto& [name, list] : weights_json["weights"].items()) {
    const auto it = index.find(name);
    if (it == index.end()) throw Error(weights_path.string() + ": unknown bone '" + name + "'");
    for (const auto& entry : list) {
      const int v = entry.at(0).get<int>();
      const float w = entry.at(1).get<float>();
      if (v < 0 || static_cast<std::size_t>(v) >= n) {
        throw Error(weights_path.string() + ": " + name + ": vertex " + std::to_string(v) +
                    " out of range");
      }
      if (w > 0) per_vertex[v].emplace_back(w, it->second);
    }
  }
  rig.influence_bone.assign(n, {0, 0, 0, 0});
  rig.influence_weight.assign(n, {0, 0, 0, 0});
  const int pelvis = rig.bone("pelvis");
  for (std::size_t v = 0; v < n; ++v) {
    auto& list = per_vertex[v];
    // Unweighted vertices (helpers only) follow the pelvis.
    if (list.empty()) list.emplace_back(1.0f, pelvis);
    std::sort(list.begin(), list.end(), [](const auto& a, const auto& b) {
      return a.first != b.first ? a.first > b.first : a.second < b.second;
    });
    float sum = 0;
    const int k = std::min<int>(Rig::kMaxInfluences, static_cast<int>(list.size()));
    for (int i = 0; i < k; ++i) sum += list[i].first;
    for (int i = 0; i < k; ++i) {
      rig.influence_bone[v][i] = list[i].second;
      rig.influence_weight[v][i] = list[i].first / sum;
    }
  }
  return rig;
}

BoneFrames bone_positions(const Rig& rig, const std::vector<Eigen::Vector3f>& vertices) {
  BoneFrames f;
  for (const RigBone& b : rig.bones) {
    f.head.push_back(mean_of(b.head, vertices));
    f.tail.push_back(mean_of(b.tail, vertices));
  }
  return f;
}

RigPose bind_pose(const Rig& rig) {
  RigPose pose;
  pose.rotation.assign(rig.bones.size(), Eigen::Quaternionf::Identity());
  return pose;
}

BoneFrames pose_bones(const Rig& rig, const BoneFrames& rest, const RigPose& pose) {
  BoneFrames out = rest;
  for (std::size_t b = 0; b < rig.bones.size(); ++b) {
    const int p = rig.bones[b].parent;
    if (p < 0) {
      out.head[b] = rest.head[b] + pose.root_offset;
    } else {
      out.head[b] = out.head[p] + pose.rotation[p] * (rest.head[b] - rest.head[p]);
    }
    out.tail[b] = out.head[b] + pose.rotation[b] * (rest.tail[b] - rest.head[b]);
  }
  return out;
}

std::vector<Eigen::Vector3f> skin(const Rig& rig, const BoneFrames& rest, const RigPose& pose,
                                  const std::vector<Eigen::Vector3f>& vertices) {
  const BoneFrames posed = pose_bones(rig, rest, pose);
  // Per bone: v' = R v + t with t = posed_head - R rest_head.
  std::vector<Eigen::Matrix3f> r(rig.bones.size());
  std::vector<Eigen::Vector3f> t(rig.bones.size());
  for (std::size_t b = 0; b < rig.bones.size(); ++b) {
    r[b] = pose.rotation[b].toRotationMatrix();
    t[b] = posed.head[b] - r[b] * rest.head[b];
  }
  std::vector<Eigen::Vector3f> out(vertices.size());
  for (std::size_t v = 0; v < vertices.size(); ++v) {
    const auto& bones = rig.influence_bone[v];
    const auto& w = rig.influence_weight[v];
    Eigen::Vector3f sum = Eigen::Vector3f::Zero();
    for (int k = 0; k < Rig::kMaxInfluences; ++k) {
      if (w[k] == 0) continue;
      sum += w[k] * (r[bones[k]] * vertices[v] + t[bones[k]]);
    }
    out[v] = sum;
  }
  return out;
}

const std::vector<BoneMapping>& bone_mapping() {
  // clip_parent == clip_child: the bone continues its parent clip bone (hand along forearm).
  static const std::vector<BoneMapping> mapping = {
      {"pelvis", motion::kPelvis, motion::kSpine},
      {"spine_01", motion::kSpine, motion::kChest},
      {"spine_02", motion::kChest, motion::kUpperChest},
      {"spine_03", motion::kUpperChest, motion::kNeckBase},
      {"neck_01", motion::kNeckBase, motion::kHeadBase},
      {"head", motion::kHeadBase, motion::kHeadTop},
      {"clavicle_l", motion::kLeftClavicle, motion::kLeftShoulder},
      {"clavicle_r", motion::kRightClavicle, motion::kRightShoulder},
      {"upperarm_l", motion::kLeftShoulder, motion::kLeftElbow},
      {"upperarm_r", motion::kRightShoulder, motion::kRightElbow},
      {"lowerarm_l", motion::kLeftElbow, motion::kLeftWrist},
      {"lowerarm_r", motion::kRightElbow, motion::kRightWrist},
      {"hand_l", motion::kLeftWrist, motion::kLeftWrist},
      {"hand_r", motion::kRightWrist, motion::kRightWrist},
      {"thigh_l", motion::kLeftHip, motion::kLeftKnee},
      {"thigh_r", motion::kRightHip, motion::kRightKnee},
      {"calf_l", motion::kLeftKnee, motion::kLeftAnkle},
      {"calf_r", motion::kRightKnee, motion::kRightAnkle},
  };
  return mapping;
}

RigPose retarget(const Rig& rig, const BoneFrames& rest, const motion::PoseRotations& global) {
  RigPose pose = bind_pose(rig);
  std::vector<bool> mapped(rig.bones.size(), false);
  // The rig bone's rest direction is taken between the rig joints that stand for the clip
  // bone's ends (spine_03's tail is not the neck joint), so those joints follow the clip.
  const motion::Pose rest_joints = skeleton_joints(rig, rest);
  for (const BoneMapping& m : bone_mapping()) {
    const int b = rig.bone(m.rig_bone);
    const Eigen::Vector3f r = m.clip_parent == m.clip_child
                                  ? (rest.tail[b] - rest.head[b]).normalized().eval()
                                  : (rest_joints[m.clip_child] - rest_joints[m.clip_parent])
                                        .cast<float>()
                                        .normalized()
                                        .eval();
    const Eigen::Vector3f d = motion::rest_direction(m.clip_child).cast<float>();
    // Swing the rig's rest bone onto our T-pose rest bone, then apply the clip's rotation.
    const Eigen::Quaternionf swing = Eigen::Quaternionf::FromTwoVectors(r, d);
    pose.rotation[b] = (global[m.clip_parent].cast<float>() * swing).normalized();
    mapped[b] = true;
  }
  const Eigen::Quaternionf root = global[motion::kPelvis].cast<float>();
  const int ankle_l = rig.bone("foot_l"), ankle_r = rig.bone("foot_r");
  for (std::size_t b = 0; b < rig.bones.size(); ++b) {
    if (mapped[b]) continue;
    const int p = rig.bones[b].parent;
    if (static_cast<int>(b) == ankle_l) {
      pose.rotation[b] = global[motion::kLeftAnkle].cast<float>();  // both rest poses: feet flat
    } else if (static_cast<int>(b) == ankle_r) {
      pose.rotation[b] = global[motion::kRightAnkle].cast<float>();
    } else {
      pose.rotation[b] = p < 0 ? root : pose.rotation[p];
    }
  }
  // Pelvis joint at the origin, like the clips.
  const BoneFrames posed = pose_bones(rig, rest, pose);
  pose.root_offset = -posed.head[rig.bone("pelvis")];
  return pose;
}

motion::Pose skeleton_joints(const Rig& rig, const BoneFrames& posed) {
  auto head = [&](const char* name) { return posed.head[rig.bone(name)].cast<double>(); };
  auto tail = [&](const char* name) { return posed.tail[rig.bone(name)].cast<double>(); };
  motion::Pose p;
  p[motion::kPelvis] = head("pelvis");
  p[motion::kLeftHip] = head("thigh_l");
  p[motion::kRightHip] = head("thigh_r");
  p[motion::kSpine] = head("spine_01");
  p[motion::kChest] = head("spine_02");
  p[motion::kUpperChest] = head("spine_03");
  p[motion::kNeckBase] = head("neck_01");
  p[motion::kHeadBase] = head("head");
  p[motion::kHeadTop] = tail("head");
  p[motion::kLeftClavicle] = head("clavicle_l");
  p[motion::kRightClavicle] = head("clavicle_r");
  p[motion::kLeftShoulder] = head("upperarm_l");
  p[motion::kRightShoulder] = head("upperarm_r");
  p[motion::kLeftElbow] = head("lowerarm_l");
  p[motion::kRightElbow] = head("lowerarm_r");
  p[motion::kLeftWrist] = head("hand_l");
  p[motion::kRightWrist] = head("hand_r");
  p[motion::kLeftKnee] = head("calf_l");
  p[motion::kRightKnee] = head("calf_r");
  p[motion::kLeftAnkle] = head("foot_l");
  p[motion::kRightAnkle] = head("foot_r");
  p[motion::kLeftToe] = tail("ball_l");
  p[motion::kRightToe] = tail("ball_r");
  return p;
}

}  // namespace wheelpose::body
