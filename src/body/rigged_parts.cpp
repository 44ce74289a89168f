#include "body/rigged_parts.h"

#include <functional>
#include <string>
#include <utility>

#include "core/error.h"

namespace wheelpose::body {

namespace {

// A hand-held aid's primitives by the hand nearest each (hand bone index, primitives), moved
// from the first frame's pose into the hand's rest frame; skinning carries them back.
std::vector<std::pair<int, std::vector<Primitive>>> aid_in_hands(const Person& person,
                                                                 const Rig& rig) {
  const int hands[2] = {rig.bone("hand_l"), rig.bone("hand_r")};
  std::vector<std::pair<int, std::vector<Primitive>>> out = {{hands[0], {}}, {hands[1], {}}};
  for (const Primitive& part : person.aid.parts) {
    const float left = (part.centre - person.posed_bones.head[hands[0]]).squaredNorm();
    const float right = (part.centre - person.posed_bones.head[hands[1]]).squaredNorm();
    auto& [bone, prims] = out[left <= right ? 0 : 1];
    const Eigen::Matrix3f to_rest = person.pose.rotation[bone].conjugate().toRotationMatrix();
    Primitive rest = part;
    rest.centre =
        person.rest_bones.head[bone] + to_rest * (part.centre - person.posed_bones.head[bone]);
    rest.axes = to_rest * part.axes;
    prims.push_back(rest);
  }
  return out;
}

}  // namespace

RiggedParts::RiggedParts(const PersonAnimation& animation, const BodyData& data) {
  WHEELPOSE_CHECK(!animation.frames.empty());
  const Rig& rig = data.rig();
  const Person& person = animation.person;
  auto skin_new_meshes = [&](const std::function<SkinWeights(const aiMesh&)>& weights) {
    for (std::size_t m = skins.size(); m < parts.meshes.size(); ++m)
      skins.push_back(weights ? std::optional(weights(*parts.meshes[m])) : std::nullopt);
  };
  add_body_mesh(parts, person.rest_vertices, person.triangles, person.skin);
  skin_new_meshes([&](const aiMesh&) { return body_skin_weights(rig, person); });
  add_chair(parts, person.chair);
  skin_new_meshes(nullptr);
  if (person.aid.type == MobilityAidType::kWalker) {
    add_primitives(parts, person.aid.parts, person.aid.colours, "mobility_aid",
                   aid_material_names());
    skin_new_meshes(nullptr);
  } else {
    for (const auto& [bone, prims] : aid_in_hands(person, rig)) {
      add_primitives(parts, prims, person.aid.colours, "mobility_aid_" + rig.bones[bone].name,
                     aid_material_names());
      skin_new_meshes(
          [&](const aiMesh& mesh) { return rigid_skin_weights(bone, mesh.mNumVertices); });
    }
  }
  for (const Garment& g : person.garments) {
    add_garment_mesh(parts, g, g.rest_vertices);
    skin_new_meshes(
        [&](const aiMesh&) { return proxy_skin_weights(rig, data.proxies().get(g.name)); });
  }
}

Eigen::Quaternionf local_rotation(const Rig& rig, const RigPose& pose, std::size_t bone) {
  const int p = rig.bones[bone].parent;
  return (p < 0 ? pose.rotation[bone] : pose.rotation[p].conjugate() * pose.rotation[bone])
      .normalized();
}

Eigen::Vector3f root_translation(const BoneFrames& rest, const RigPose& pose, std::size_t bone) {
  return rest.head[bone] + pose.root_offset;
}

}  // namespace wheelpose::body
