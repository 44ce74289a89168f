#include "body/rigged_fbx.h"

#include <assimp/material.h>
#include <assimp/scene.h>

#include <map>
#include <numbers>
#include <string>
#include <utility>

#include "core/atomic_file.h"
#include "core/error.h"
#include "motion/euler_curves.h"
#include "motion/fbx_binary.h"
#include "motion/fbx_scene.h"
#include "motion/fbx_time.h"

namespace wheelpose::body {

namespace {

namespace fbx = motion::fbx;

constexpr const char* kRootName = "wheelpose_person";

[[noreturn]] void reject(const std::string& what) {
  throw Error("body export: cannot write FBX: " + what, ErrorKind::kBadInput);
}

void check_name(std::string_view kind, std::string_view name) {
  if (auto problem = fbx::name_problem(name)) {
    reject(std::string(kind) + " '" + fbx::printable(name) + "' " + *problem);
  }
}

fbx::MeshGeometry geometry_of(const aiMesh& mesh) {
  fbx::MeshGeometry geometry;
  for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
    const aiVector3D& p = mesh.mVertices[v];
    const aiVector3D& n = mesh.mNormals[v];
    geometry.positions.emplace_back(p.x, p.y, p.z);
    geometry.normals.emplace_back(n.x, n.y, n.z);
  }
  for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
    const unsigned* index = mesh.mFaces[f].mIndices;
    geometry.triangles.push_back({index[0], index[1], index[2]});
  }
  return geometry;
}

// One cluster per bone that moves any vertex, in rig order.
std::vector<fbx::Cluster> clusters_of(const SkinWeights& skin, const Rig& rig,
                                      const BoneFrames& rest,
                                      const std::vector<std::int64_t>& bone_models) {
  std::map<int, fbx::Cluster> by_bone;
  for (std::size_t v = 0; v < skin.bone.size(); ++v) {
    for (int k = 0; k < Rig::kMaxInfluences; ++k) {
      const int bone = skin.bone[v][k];
      if (bone < 0 || skin.weight[v][k] <= 0) continue;
      fbx::Cluster& cluster = by_bone[bone];
      cluster.indexes.push_back(static_cast<std::int32_t>(v));
      cluster.weights.push_back(skin.weight[v][k]);
    }
  }
  std::vector<fbx::Cluster> clusters;
  for (auto& [bone, cluster] : by_bone) {
    cluster.name = rig.bones[bone].name;
    cluster.bone_model = bone_models[bone];
    cluster.bind_position = rest.head[bone].cast<double>();
    clusters.push_back(std::move(cluster));
  }
  return clusters;
}

Eigen::Vector3d diffuse_colour(const aiMaterial& material) {
  aiColor4D colour(1, 1, 1, 1);
  material.Get(AI_MATKEY_COLOR_DIFFUSE, colour);
  return {colour.r, colour.g, colour.b};
}

std::string material_name(const aiMaterial& material) {
  aiString name;
  material.Get(AI_MATKEY_NAME, name);
  return name.C_Str();
}

}  // namespace

std::vector<fbx::Node> rigged_person_fbx_document(const PersonAnimation& animation,
                                                  const BodyData& data) {
  WHEELPOSE_CHECK(!animation.frames.empty());
  const std::string name = animation.name.empty() ? "motion" : animation.name;
  check_name("the clip name", name);
  if (!(animation.fps >= motion::kMinFrameRate && animation.fps <= motion::kMaxFrameRate)) {
    reject("fps " + std::to_string(animation.fps) + " is outside what FBX time can hold");
  }
  const Rig& rig = data.rig();
  const BoneFrames& rest = animation.person.rest_bones;
  const RiggedParts rigged(animation, data);
  const SceneParts& parts = rigged.parts;

  fbx::SceneBuilder scene;
  const std::int64_t root =
      scene.add_model(kRootName, "Null", 0, Eigen::Vector3d::Zero(), motion::EulerOrder::kXYZ);
  std::vector<std::int64_t> mesh_models;
  for (const aiMesh* mesh : parts.meshes) {
    check_name("the mesh name", mesh->mName.C_Str());
    mesh_models.push_back(scene.add_model(mesh->mName.C_Str(), "Mesh", root,
                                          Eigen::Vector3d::Zero(), motion::EulerOrder::kXYZ));
  }

  // Bones parent first (the rig's order), each with the Euler order that suits its motion.
  const std::size_t bones = rig.bones.size();
  std::vector<std::vector<Eigen::Quaterniond>> rotations(bones);
  std::vector<motion::EulerOrder> orders(bones);
  std::vector<std::int64_t> bone_models(bones);
  for (std::size_t b = 0; b < bones; ++b) {
    for (const RigPose& pose : animation.frames) {
      rotations[b].push_back(local_rotation(rig, pose, b).cast<double>());
    }
    orders[b] = motion::best_euler_order(rotations[b]);
    const int p = rig.bones[b].parent;
    const Eigen::Vector3f offset = p < 0 ? rest.head[b] : (rest.head[b] - rest.head[p]).eval();
    bone_models[b] = scene.add_bone(rig.bones[b].name, p < 0 ? root : bone_models[p],
                                    offset.cast<double>(), orders[b]);
  }

  std::vector<std::int64_t> materials(parts.materials.size(), 0);
  for (std::size_t m = 0; m < parts.meshes.size(); ++m) {
    const aiMesh& mesh = *parts.meshes[m];
    const std::int64_t geometry =
        scene.add_geometry(mesh_models[m], mesh.mName.C_Str(), geometry_of(mesh));
    std::int64_t& material = materials.at(mesh.mMaterialIndex);
    if (material == 0) {
      const aiMaterial& source = *parts.materials[mesh.mMaterialIndex];
      check_name("the material name", material_name(source));
      material = scene.add_material(material_name(source), diffuse_colour(source));
    }
    scene.use_material(material, mesh_models[m]);
    if (rigged.skins[m]) {
      scene.add_skin(geometry, mesh.mName.C_Str(),
                     clusters_of(*rigged.skins[m], rig, rest, bone_models));
    }
  }
  std::vector<std::pair<std::int64_t, Eigen::Vector3d>> bind_nodes = {
      {root, Eigen::Vector3d::Zero()}};
  for (std::int64_t model : mesh_models) bind_nodes.emplace_back(model, Eigen::Vector3d::Zero());
  for (std::size_t b = 0; b < bones; ++b) {
    bind_nodes.emplace_back(bone_models[b], rest.head[b].cast<double>());
  }
  scene.add_bind_pose(bind_nodes);

  const motion::FrameRate rate = motion::exact_frame_rate(animation.fps);
  std::vector<std::int64_t> times;
  for (std::size_t f = 0; f < animation.frames.size(); ++f) {
    times.push_back(motion::fbx_frame_time(static_cast<std::int64_t>(f), rate));
  }
  scene.begin_animation(name, std::move(times));
  for (std::size_t b = 0; b < bones; ++b) {
    if (rig.bones[b].parent < 0) {
      std::vector<Eigen::Vector3d> translations;
      for (const RigPose& pose : animation.frames) {
        translations.push_back(root_translation(rest, pose, b).cast<double>());
      }
      scene.add_curves(bone_models[b], "T", "Lcl Translation", translations);
    }
    std::vector<Eigen::Vector3d> degrees = motion::continuous_euler(rotations[b], orders[b]);
    for (Eigen::Vector3d& angles : degrees) angles *= 180.0 / std::numbers::pi;
    scene.add_curves(bone_models[b], "R", "Lcl Rotation", degrees);
  }
  return scene.finish(fbx::Encoding::kBinary, rate, animation.fps);
}

void write_rigged_person_fbx(const PersonAnimation& animation, const BodyData& data,
                             const std::filesystem::path& path) {
  write_file_atomic(path, motion::fbx::encode_binary(rigged_person_fbx_document(animation, data),
                                                     motion::fbx::kVersion));
}

}  // namespace wheelpose::body
