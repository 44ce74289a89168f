#include "motion/export_gltf.h"

#include <assimp/scene.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.h"
#include "motion/glb_file.h"
#include "motion/stick_figure.h"

namespace wheelpose::motion {

namespace {

aiVector3D to_ai(const Eigen::Vector3d& v) {
  return aiVector3D(static_cast<ai_real>(v.x()), static_cast<ai_real>(v.y()),
                    static_cast<ai_real>(v.z()));
}

aiMatrix4x4 translation(const Eigen::Vector3d& v) {
  aiMatrix4x4 m;
  aiMatrix4x4::Translation(to_ai(v), m);
  return m;
}

constexpr const char* kRootNodeName = "wheelpose_root";
constexpr const char* kMeshName = "stick_figure";

// Assimp's glTF exporter aborts ("two objects with the same ID") when the animation is named
// like a node, so a motion called e.g. "pelvis" gets a suffix.
std::string animation_name(const SkeletalMotion& motion) {
  std::string name = motion.name.empty() ? "motion" : motion.name;
  if (name == kRootNodeName || name == kMeshName || joint_from_name(name)) name += "_motion";
  return name;
}

std::vector<int> children_of(int joint) {
  std::vector<int> children;
  for (int j = 0; j < kJointCount; ++j) {
    if (joint_parent(j) == joint) children.push_back(j);
  }
  return children;
}

aiNode* make_joint_node(const SkeletalMotion& motion, int joint, const Eigen::Vector3d& bind_root,
                        aiNode* parent) {
  auto* node = new aiNode(std::string(joint_name(joint)));
  node->mParent = parent;
  node->mTransformation =
      translation(joint_parent(joint) < 0 ? bind_root : motion.rest_offsets[joint]);
  const std::vector<int> children = children_of(joint);
  if (!children.empty()) {
    node->mNumChildren = static_cast<unsigned>(children.size());
    node->mChildren = new aiNode*[children.size()];
    for (std::size_t i = 0; i < children.size(); ++i) {
      node->mChildren[i] = make_joint_node(motion, children[i], bind_root, node);
    }
  }
  return node;
}

aiMesh* make_mesh(const Pose& bind_pose) {
  const StickMesh stick = build_stick_mesh(bind_pose);
  auto* mesh = new aiMesh;
  mesh->mName = kMeshName;
  mesh->mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
  mesh->mMaterialIndex = 0;
  mesh->mNumVertices = static_cast<unsigned>(stick.positions.size());
  mesh->mVertices = new aiVector3D[mesh->mNumVertices];
  mesh->mNormals = new aiVector3D[mesh->mNumVertices];
  for (unsigned i = 0; i < mesh->mNumVertices; ++i) {
    mesh->mVertices[i] = to_ai(stick.positions[i].cast<double>());
    mesh->mNormals[i] = to_ai(stick.normals[i].cast<double>());
  }
  mesh->mNumFaces = static_cast<unsigned>(stick.triangles.size());
  mesh->mFaces = new aiFace[mesh->mNumFaces];
  for (unsigned i = 0; i < mesh->mNumFaces; ++i) {
    aiFace& face = mesh->mFaces[i];
    face.mNumIndices = 3;
    face.mIndices = new unsigned[3];
    for (int k = 0; k < 3; ++k) face.mIndices[k] = stick.triangles[i][k];
  }
  // Every joint is a bone, weighted or not, so that importers build the full armature.
  mesh->mNumBones = kJointCount;
  mesh->mBones = new aiBone*[kJointCount];
  for (int joint = 0; joint < kJointCount; ++joint) {
    auto* bone = new aiBone;
    bone->mName = std::string(joint_name(joint));
    // Inverse bind matrix: joints carry no rotation in the bind pose, only their position.
    bone->mOffsetMatrix = translation(-bind_pose[joint]);
    std::vector<unsigned> vertices;
    for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
      if (stick.vertex_joint[v] == joint) vertices.push_back(v);
    }
    bone->mNumWeights = static_cast<unsigned>(vertices.size());
    if (!vertices.empty()) {
      bone->mWeights = new aiVertexWeight[vertices.size()];
      for (std::size_t i = 0; i < vertices.size(); ++i) {
        bone->mWeights[i] = aiVertexWeight(vertices[i], 1.0f);
      }
    }
    mesh->mBones[joint] = bone;
  }
  return mesh;
}

// Key times are mTime / mTicksPerSecond seconds: ticks equal to frame indices and ticks per
// second equal to fps give exact frame times.
aiAnimation* make_animation(const SkeletalMotion& motion) {
  auto* animation = new aiAnimation;
  animation->mName = animation_name(motion);
  const double last = static_cast<double>(motion.frame_count() - 1);
  animation->mTicksPerSecond = motion.fps;
  animation->mDuration = last;
  auto key_time = [](std::size_t frame) { return static_cast<double>(frame); };
  const std::size_t frames = motion.frame_count();
  animation->mNumChannels = kJointCount;
  animation->mChannels = new aiNodeAnim*[kJointCount];
  for (int joint = 0; joint < kJointCount; ++joint) {
    auto* channel = new aiNodeAnim;
    channel->mNodeName = std::string(joint_name(joint));
    const bool root = joint_parent(joint) < 0;
    // Non-root joints keep their rest offset; exporters still want one key of each kind.
    channel->mNumPositionKeys = root ? static_cast<unsigned>(frames) : 1;
    channel->mPositionKeys = new aiVectorKey[channel->mNumPositionKeys];
    for (unsigned k = 0; k < channel->mNumPositionKeys; ++k) {
      channel->mPositionKeys[k] = aiVectorKey(
          key_time(k), to_ai(root ? motion.root_positions[k] : motion.rest_offsets[joint]));
    }
    channel->mNumRotationKeys = static_cast<unsigned>(frames);
    channel->mRotationKeys = new aiQuatKey[frames];
    Eigen::Quaterniond previous = Eigen::Quaterniond::Identity();
    for (std::size_t f = 0; f < frames; ++f) {
      Eigen::Quaterniond q = motion.local_rotations[f][joint].normalized();
      // Same rotation, but the sign nearest the previous key so linear blending takes the
      // short way.
      if (q.dot(previous) < 0) q.coeffs() = -q.coeffs();
      previous = q;
      channel->mRotationKeys[f] = aiQuatKey(
          key_time(f), aiQuaternion(static_cast<ai_real>(q.w()), static_cast<ai_real>(q.x()),
                                    static_cast<ai_real>(q.y()), static_cast<ai_real>(q.z())));
    }
    channel->mNumScalingKeys = 1;
    channel->mScalingKeys = new aiVectorKey[1];
    channel->mScalingKeys[0] = aiVectorKey(0.0, aiVector3D(1, 1, 1));
    animation->mChannels[joint] = channel;
  }
  return animation;
}

std::unique_ptr<aiScene> make_scene(const SkeletalMotion& motion) {
  auto scene = std::make_unique<aiScene>();
  const Eigen::Vector3d bind_root = bind_root_position(motion);
  const Pose bind_pose = rest_pose(motion, bind_root);

  scene->mRootNode = new aiNode(kRootNodeName);
  auto* mesh_node = new aiNode(kMeshName);
  mesh_node->mParent = scene->mRootNode;
  mesh_node->mNumMeshes = 1;
  mesh_node->mMeshes = new unsigned[1]{0};
  scene->mRootNode->mNumChildren = 2;
  scene->mRootNode->mChildren =
      new aiNode* [2] { mesh_node, make_joint_node(motion, kPelvis, bind_root, scene->mRootNode) };

  scene->mNumMaterials = 1;
  scene->mMaterials = new aiMaterial*[1];
  auto* material = new aiMaterial;
  const aiString material_name(kMeshName);
  material->AddProperty(&material_name, AI_MATKEY_NAME);
  const aiColor4D grey(0.6f, 0.6f, 0.6f, 1.0f);
  material->AddProperty(&grey, 1, AI_MATKEY_COLOR_DIFFUSE);
  scene->mMaterials[0] = material;

  scene->mNumMeshes = 1;
  scene->mMeshes = new aiMesh* [1] { make_mesh(bind_pose) };
  scene->mNumAnimations = 1;
  scene->mAnimations = new aiAnimation* [1] { make_animation(motion) };
  return scene;
}

}  // namespace

void write_glb(const SkeletalMotion& motion, const std::filesystem::path& path) {
  check_exportable(motion, "glTF");
  const std::unique_ptr<aiScene> scene = make_scene(motion);
  write_glb_file(*scene, path);
}

}  // namespace wheelpose::motion
