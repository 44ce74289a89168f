#include "body/rigged_glb.h"

#include <assimp/material.h>
#include <assimp/scene.h>

#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "body/rigged_parts.h"
#include "core/error.h"
#include "motion/glb_file.h"

namespace wheelpose::body {

namespace {

using motion::GlbBuilder;
using Json = nlohmann::ordered_json;

Json vec3(const Eigen::Vector3f& v) { return Json::array({v.x(), v.y(), v.z()}); }

// Positions (with the bounds glTF requires), normals, triangles and, when skinned, JOINTS_0 and
// WEIGHTS_0; returns the glTF mesh.
Json mesh_json(GlbBuilder& glb, const aiMesh& mesh, const std::optional<SkinWeights>& skin) {
  const unsigned n = mesh.mNumVertices;
  std::vector<float> positions, normals;
  std::vector<float> lo(3, std::numeric_limits<float>::max());
  std::vector<float> hi(3, std::numeric_limits<float>::lowest());
  for (unsigned v = 0; v < n; ++v) {
    const aiVector3D& p = mesh.mVertices[v];
    const aiVector3D& q = mesh.mNormals[v];
    for (int k = 0; k < 3; ++k) {
      positions.push_back(p[k]);
      normals.push_back(q[k]);
      lo[k] = std::min(lo[k], p[k]);
      hi[k] = std::max(hi[k], p[k]);
    }
  }
  std::vector<std::uint32_t> indices;
  for (unsigned f = 0; f < mesh.mNumFaces; ++f)
    for (unsigned k = 0; k < 3; ++k) indices.push_back(mesh.mFaces[f].mIndices[k]);
  Json attributes;
  attributes["POSITION"] =
      glb.add_accessor(positions, n, GlbBuilder::kFloat, "VEC3", GlbBuilder::kVertices, lo, hi);
  attributes["NORMAL"] =
      glb.add_accessor(normals, n, GlbBuilder::kFloat, "VEC3", GlbBuilder::kVertices);
  if (skin) {
    std::vector<std::uint8_t> joints;
    std::vector<float> weights;
    for (unsigned v = 0; v < n; ++v) {
      for (int k = 0; k < Rig::kMaxInfluences; ++k) {
        // An unused slot names joint 0 with weight 0, as glTF allows.
        joints.push_back(static_cast<std::uint8_t>(std::max(skin->bone[v][k], 0)));
        weights.push_back(skin->weight[v][k]);
      }
    }
    attributes["JOINTS_0"] =
        glb.add_accessor(joints, n, GlbBuilder::kUnsignedByte, "VEC4", GlbBuilder::kVertices);
    attributes["WEIGHTS_0"] =
        glb.add_accessor(weights, n, GlbBuilder::kFloat, "VEC4", GlbBuilder::kVertices);
  }
  const int index_accessor = glb.add_accessor(indices, indices.size(), GlbBuilder::kUnsignedInt,
                                              "SCALAR", GlbBuilder::kIndices);
  return {{"name", mesh.mName.C_Str()},
          {"primitives", Json::array({{{"attributes", attributes},
                                       {"indices", index_accessor},
                                       {"material", mesh.mMaterialIndex},
                                       {"mode", 4}}})}};
}

// The base colour the static export gives the same material.
Json material_json(const aiMaterial& material) {
  aiString name;
  material.Get(AI_MATKEY_NAME, name);
  aiColor4D colour(1, 1, 1, 1);
  material.Get(AI_MATKEY_COLOR_DIFFUSE, colour);
  return {{"name", name.C_Str()},
          {"pbrMetallicRoughness",
           {{"baseColorFactor", Json::array({colour.r, colour.g, colour.b, 1.0f})},
            {"metallicFactor", 0.0f}}}};
}

// One sampler per joint rotation and one for each root joint's translation, all keyed at
// frame / fps seconds.
Json animation_json(GlbBuilder& glb, const PersonAnimation& animation, const Rig& rig,
                    const BoneFrames& rest, int first_joint_node) {
  const std::size_t frames = animation.frames.size();
  std::vector<float> times(frames);
  for (std::size_t f = 0; f < frames; ++f)
    times[f] = static_cast<float>(static_cast<double>(f) / animation.fps);
  const int input = glb.add_accessor(times, frames, GlbBuilder::kFloat, "SCALAR",
                                     GlbBuilder::kNoTarget, {times.front()}, {times.back()});
  Json samplers = Json::array(), channels = Json::array();
  auto add = [&](const std::vector<float>& values, const char* type, int node, const char* path) {
    const int output = glb.add_accessor(values, frames, GlbBuilder::kFloat, type);
    channels.push_back(
        {{"sampler", samplers.size()}, {"target", {{"node", node}, {"path", path}}}});
    samplers.push_back({{"input", input}, {"output", output}, {"interpolation", "LINEAR"}});
  };
  for (std::size_t b = 0; b < rig.bones.size(); ++b) {
    const int p = rig.bones[b].parent;
    const int node = first_joint_node + static_cast<int>(b);
    std::vector<float> rotations;
    Eigen::Quaternionf previous = Eigen::Quaternionf::Identity();
    for (const RigPose& pose : animation.frames) {
      Eigen::Quaternionf q = local_rotation(rig, pose, b);
      // The sign nearest the previous key, so linear blending takes the short way.
      if (q.dot(previous) < 0) q.coeffs() = -q.coeffs();
      previous = q;
      rotations.insert(rotations.end(), {q.x(), q.y(), q.z(), q.w()});
    }
    add(rotations, "VEC4", node, "rotation");
    if (p >= 0) continue;  // other joints keep their rest offset from their parent
    std::vector<float> translations;
    for (const RigPose& pose : animation.frames) {
      const Eigen::Vector3f t = root_translation(rest, pose, b);
      translations.insert(translations.end(), {t.x(), t.y(), t.z()});
    }
    add(translations, "VEC3", node, "translation");
  }
  return {{"name", animation.name.empty() ? "motion" : animation.name},
          {"channels", channels},
          {"samplers", samplers}};
}

}  // namespace

void write_rigged_person_glb(const PersonAnimation& animation, const BodyData& data,
                             const std::filesystem::path& path) {
  WHEELPOSE_CHECK(!animation.frames.empty());
  const Rig& rig = data.rig();
  const BoneFrames& rest = animation.person.rest_bones;
  const RiggedParts rigged(animation, data);
  const SceneParts& parts = rigged.parts;
  const auto& skins = rigged.skins;

  GlbBuilder glb;
  Json& doc = glb.json;
  doc["asset"] = {{"version", "2.0"}, {"generator", "wheelpose body export --rigged"}};
  doc["scene"] = 0;
  // Skinned meshes are scene roots (glTF ignores their parents' transforms; the joints, under
  // the person node, carry them).
  Json scene_nodes = Json::array({0});
  // Node 0 is the person; then one node per mesh; then the joints in rig order.
  const int first_joint = 1 + static_cast<int>(parts.meshes.size());
  Json nodes = Json::array(), meshes = Json::array(), materials = Json::array();
  Json root_children = Json::array();
  nodes.push_back({{"name", "wheelpose_person"}});
  for (std::size_t m = 0; m < parts.meshes.size(); ++m) {
    const aiMesh& mesh = *parts.meshes[m];
    meshes.push_back(mesh_json(glb, mesh, skins[m]));
    Json node = {{"name", std::string(mesh.mName.C_Str()) + "_node"}, {"mesh", m}};
    if (skins[m]) node["skin"] = 0;
    nodes.push_back(std::move(node));
    (skins[m] ? scene_nodes : root_children).push_back(1 + m);
  }
  for (const aiMaterial* material : parts.materials) materials.push_back(material_json(*material));
  Json joints = Json::array();
  std::vector<float> inverse_bind;
  int skeleton = -1;
  for (std::size_t b = 0; b < rig.bones.size(); ++b) {
    const int p = rig.bones[b].parent;
    Json node = {
        {"name", rig.bones[b].name},
        {"translation", vec3(p < 0 ? rest.head[b] : (rest.head[b] - rest.head[p]).eval())}};
    Json children = Json::array();
    for (std::size_t c = 0; c < rig.bones.size(); ++c)
      if (rig.bones[c].parent == static_cast<int>(b)) children.push_back(first_joint + c);
    if (!children.empty()) node["children"] = children;
    nodes.push_back(std::move(node));
    joints.push_back(first_joint + b);
    if (p < 0) {
      root_children.push_back(first_joint + b);
      if (skeleton < 0) skeleton = first_joint + static_cast<int>(b);
    }
    // Inverse bind matrix (column-major): the rest pose has no rotations, only positions.
    const Eigen::Vector3f t = -rest.head[b];
    inverse_bind.insert(inverse_bind.end(),
                        {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, t.x(), t.y(), t.z(), 1});
  }
  nodes[0]["children"] = root_children;
  doc["scenes"] = Json::array({{{"nodes", scene_nodes}}});
  doc["nodes"] = nodes;
  doc["meshes"] = meshes;
  doc["materials"] = materials;
  doc["skins"] =
      Json::array({{{"name", "game_engine_rig"},
                    {"inverseBindMatrices",
                     glb.add_accessor(inverse_bind, rig.bones.size(), GlbBuilder::kFloat, "MAT4")},
                    {"skeleton", skeleton},
                    {"joints", joints}}});
  doc["animations"] = Json::array({animation_json(glb, animation, rig, rest, first_joint)});
  glb.write(path);
}

}  // namespace wheelpose::body
