#include "motion/export_gltf.h"

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <assimp/Importer.hpp>
#include <cmath>
#include <filesystem>
#include <functional>
#include <map>
#include <numbers>
#include <string>

#include "core/atomic_file.h"
#include "core/error.h"
#include "motion/export_bvh.h"
#include "motion/export_test_support.h"

namespace wheelpose::motion {

// Shared with the other export tests (export_test_support.h).
namespace export_test {

// A motion built by hand: the T-pose skeleton with default bone lengths, the root moving along
// +Z and rising, the left elbow bending to 90° about +Y (forearm swings from +X to -Z), the
// right shoulder raising the arm about +Z, the spine twisting about its own axis and the pelvis
// turning about +Y.
SkeletalMotion make_test_motion(int frames, double fps) {
  SkeletalMotion motion;
  motion.name = "hand_made";
  motion.fps = fps;
  for (int j = 0; j < kJointCount; ++j) {
    motion.rest_offsets[j] = rest_direction(j) * default_bone_length(j);
  }
  for (int f = 0; f < frames; ++f) {
    const double s = frames > 1 ? static_cast<double>(f) / (frames - 1) : 0.0;
    const double half_pi = std::numbers::pi / 2;
    motion.root_positions.emplace_back(0.1 * s, 0.9 + 0.05 * s, 0.5 * s);
    PoseRotations rotations;
    rotations.fill(Eigen::Quaterniond::Identity());
    rotations[kPelvis] = Eigen::AngleAxisd(0.6 * s, Eigen::Vector3d::UnitY());
    rotations[kLeftElbow] = Eigen::AngleAxisd(half_pi * s, Eigen::Vector3d::UnitY());
    rotations[kRightShoulder] = Eigen::AngleAxisd(-1.2 * s, Eigen::Vector3d::UnitZ());
    rotations[kSpine] = Eigen::AngleAxisd(0.4 * s, Eigen::Vector3d::UnitY()) *
                        Eigen::AngleAxisd(0.3 * s, Eigen::Vector3d::UnitX());
    rotations[kLeftKnee] = Eigen::AngleAxisd(half_pi * s, Eigen::Vector3d::UnitX());
    rotations[kHeadBase] = Eigen::AngleAxisd(2.5 * s, Eigen::Vector3d(1, 2, 3).normalized());
    motion.local_rotations.push_back(rotations);
  }
  return motion;
}

namespace {

template <typename Key>
std::size_t key_before(const Key* keys, unsigned count, double t) {
  std::size_t i = 0;
  while (i + 1 < count && keys[i + 1].mTime <= t) ++i;
  return i;
}

aiVector3D sample(const aiVectorKey* keys, unsigned count, double t) {
  const std::size_t i = key_before(keys, count, t);
  if (i + 1 >= count || t <= keys[i].mTime) return keys[i].mValue;
  const double w = (t - keys[i].mTime) / (keys[i + 1].mTime - keys[i].mTime);
  return keys[i].mValue + static_cast<ai_real>(w) * (keys[i + 1].mValue - keys[i].mValue);
}

aiQuaternion sample(const aiQuatKey* keys, unsigned count, double t) {
  const std::size_t i = key_before(keys, count, t);
  if (i + 1 >= count || t <= keys[i].mTime) return keys[i].mValue;
  const double w = (t - keys[i].mTime) / (keys[i + 1].mTime - keys[i].mTime);
  aiQuaternion out;
  aiQuaternion::Interpolate(out, keys[i].mValue, keys[i + 1].mValue, static_cast<ai_real>(w));
  return out.Normalize();
}

}  // namespace

double ticks_per_second(const aiAnimation& animation) {
  return animation.mTicksPerSecond > 0 ? animation.mTicksPerSecond : 1.0;
}

// World positions of the nodes named like our joints at `seconds` into the scene's first
// animation: every node's local transform comes from its channel where one exists (linear
// interpolation between keys, as glTF players do), otherwise from its static transform.
Pose scene_joint_positions(const aiScene& scene, double seconds) {
  std::map<std::string, const aiNodeAnim*> channels;
  const aiAnimation* animation = scene.mNumAnimations > 0 ? scene.mAnimations[0] : nullptr;
  if (animation != nullptr) {
    for (unsigned c = 0; c < animation->mNumChannels; ++c) {
      channels[animation->mChannels[c]->mNodeName.C_Str()] = animation->mChannels[c];
    }
  }
  const double t = animation != nullptr ? seconds * ticks_per_second(*animation) : 0.0;
  Pose pose;
  std::array<bool, kJointCount> found{};
  std::function<void(const aiNode*, const aiMatrix4x4&)> visit = [&](const aiNode* node,
                                                                     const aiMatrix4x4& parent) {
    aiMatrix4x4 local = node->mTransformation;
    auto it = channels.find(node->mName.C_Str());
    if (it != channels.end()) {
      const aiNodeAnim* ch = it->second;
      aiVector3D scaling, position;
      aiQuaternion rotation;
      local.Decompose(scaling, rotation, position);
      if (ch->mNumPositionKeys > 0) position = sample(ch->mPositionKeys, ch->mNumPositionKeys, t);
      if (ch->mNumRotationKeys > 0) rotation = sample(ch->mRotationKeys, ch->mNumRotationKeys, t);
      if (ch->mNumScalingKeys > 0) scaling = sample(ch->mScalingKeys, ch->mNumScalingKeys, t);
      local = aiMatrix4x4(scaling, rotation, position);
    }
    const aiMatrix4x4 world = parent * local;
    if (auto joint = joint_from_name(node->mName.C_Str())) {
      EXPECT_FALSE(found[*joint]) << "two nodes named " << node->mName.C_Str();
      found[*joint] = true;
      pose[*joint] = Eigen::Vector3d(world.a4, world.b4, world.c4);
    }
    for (unsigned i = 0; i < node->mNumChildren; ++i) visit(node->mChildren[i], world);
  };
  visit(scene.mRootNode, aiMatrix4x4());
  for (int j = 0; j < kJointCount; ++j) {
    EXPECT_TRUE(found[j]) << "no node named " << joint_name(j);
  }
  return pose;
}

void expect_plays_like(const aiScene& scene, const SkeletalMotion& motion, double tolerance) {
  for (std::size_t f = 0; f < motion.frame_count(); ++f) {
    const Pose expected = forward_kinematics(motion, f);
    const Pose actual = scene_joint_positions(scene, static_cast<double>(f) / motion.fps);
    for (int j = 0; j < kJointCount; ++j) {
      EXPECT_LT((actual[j] - expected[j]).norm(), tolerance)
          << "frame " << f << " joint " << joint_name(j) << ": got " << actual[j].transpose()
          << ", expected " << expected[j].transpose();
    }
  }
}

std::filesystem::path temp_dir(const std::string& name) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("wheelpose_export_test_" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace export_test

namespace {

using export_test::expect_plays_like;
using export_test::make_test_motion;
using export_test::temp_dir;

const aiScene* import(Assimp::Importer& importer, const std::filesystem::path& path) {
  const aiScene* scene = importer.ReadFile(path.string(), 0);
  EXPECT_NE(scene, nullptr) << importer.GetErrorString();
  return scene;
}

void expect_animation_timing(const aiScene& scene, const SkeletalMotion& motion) {
  ASSERT_EQ(scene.mNumAnimations, 1u);
  const aiAnimation& animation = *scene.mAnimations[0];
  const double last = static_cast<double>(motion.frame_count() - 1);
  EXPECT_NEAR(animation.mDuration / export_test::ticks_per_second(animation), last / motion.fps,
              1e-6);
  ASSERT_EQ(animation.mNumChannels, static_cast<unsigned>(kJointCount));
  for (unsigned c = 0; c < animation.mNumChannels; ++c) {
    const aiNodeAnim& channel = *animation.mChannels[c];
    ASSERT_TRUE(joint_from_name(channel.mNodeName.C_Str())) << channel.mNodeName.C_Str();
    ASSERT_EQ(channel.mNumRotationKeys, motion.frame_count()) << channel.mNodeName.C_Str();
    for (unsigned k = 0; k < channel.mNumRotationKeys; ++k) {
      EXPECT_NEAR(channel.mRotationKeys[k].mTime / export_test::ticks_per_second(animation),
                  k / motion.fps, 1e-6);
    }
  }
}

TEST(ExportGltf, GlbPlaysBackAsForwardKinematics) {
  const auto dir = temp_dir("glb");
  const SkeletalMotion motion = make_test_motion(9, 30.0);
  write_glb(motion, dir / "hand_made.glb");
  const std::string bytes = read_file(dir / "hand_made.glb");
  ASSERT_GT(bytes.size(), 20u);
  EXPECT_EQ(bytes.substr(0, 4), "glTF");
  EXPECT_EQ(bytes[4], 2);  // container version 2
  Assimp::Importer importer;
  const aiScene* scene = import(importer, dir / "hand_made.glb");
  ASSERT_NE(scene, nullptr);
  expect_animation_timing(*scene, motion);
  expect_plays_like(*scene, motion, 1e-4);
  // Same motion, same bytes.
  write_glb(motion, dir / "again.glb");
  EXPECT_TRUE(read_file(dir / "again.glb") == bytes);
}

TEST(ExportGltf, GlbSkinBindsEveryJointAtTheRestPose) {
  const auto dir = temp_dir("skin");
  const SkeletalMotion motion = make_test_motion(3, 20.0);
  write_glb(motion, dir / "skin.glb");
  Assimp::Importer importer;
  const aiScene* scene = import(importer, dir / "skin.glb");
  ASSERT_NE(scene, nullptr);
  ASSERT_EQ(scene->mNumMeshes, 1u);
  const aiMesh& mesh = *scene->mMeshes[0];
  ASSERT_EQ(mesh.mNumBones, static_cast<unsigned>(kJointCount));
  // Rest pose with the animation ignored: the static node transforms.
  std::map<std::string, aiMatrix4x4> bind;
  std::function<void(const aiNode*, const aiMatrix4x4&)> visit = [&](const aiNode* node,
                                                                     const aiMatrix4x4& parent) {
    const aiMatrix4x4 world = parent * node->mTransformation;
    bind[node->mName.C_Str()] = world;
    for (unsigned i = 0; i < node->mNumChildren; ++i) visit(node->mChildren[i], world);
  };
  visit(scene->mRootNode, aiMatrix4x4());
  std::vector<int> weighted_vertices(mesh.mNumVertices, 0);
  double lowest = 1e9;
  for (unsigned b = 0; b < mesh.mNumBones; ++b) {
    const aiBone& bone = *mesh.mBones[b];
    ASSERT_TRUE(joint_from_name(bone.mName.C_Str())) << bone.mName.C_Str();
    ASSERT_TRUE(bind.count(bone.mName.C_Str()));
    const aiMatrix4x4 product = bind[bone.mName.C_Str()] * bone.mOffsetMatrix;
    EXPECT_TRUE(product.Equal(aiMatrix4x4(), 1e-5f)) << bone.mName.C_Str();
    EXPECT_GT(bone.mNumWeights, 0u) << bone.mName.C_Str();
    for (unsigned w = 0; w < bone.mNumWeights; ++w) {
      EXPECT_FLOAT_EQ(bone.mWeights[w].mWeight, 1.0f);
      ++weighted_vertices[bone.mWeights[w].mVertexId];
    }
    lowest = std::min<double>(lowest, bind[bone.mName.C_Str()].b4);
  }
  for (unsigned v = 0; v < mesh.mNumVertices; ++v) EXPECT_EQ(weighted_vertices[v], 1) << v;
  // The bind pose stands on the floor, upright, toes towards +Z, left hand at +X.
  EXPECT_NEAR(lowest, 0.0, 1e-6);
  EXPECT_GT(bind["head_top"].b4, bind["pelvis"].b4 + 0.5);
  EXPECT_GT(bind["left_toe"].c4, bind["left_ankle"].c4 + 0.1);
  EXPECT_GT(bind["left_wrist"].a4, 0.5);
  EXPECT_LT(bind["right_wrist"].a4, -0.5);
}

TEST(ExportGltf, MotionNamedLikeAJointStillExports) {
  // Assimp's glTF writer fails when the animation and a node share a name.
  const auto dir = temp_dir("names");
  SkeletalMotion motion = make_test_motion(2, 10.0);
  motion.name = "pelvis";
  write_glb(motion, dir / "pelvis.glb");
  Assimp::Importer importer;
  const aiScene* scene = import(importer, dir / "pelvis.glb");
  ASSERT_NE(scene, nullptr);
  ASSERT_EQ(scene->mNumAnimations, 1u);
  EXPECT_STREQ(scene->mAnimations[0]->mName.C_Str(), "pelvis_motion");
}

TEST(ExportGltf, RejectsBadMotionsAndPaths) {
  const SkeletalMotion motion = make_test_motion(3, 30.0);
  EXPECT_THROW(write_glb(motion, "/nonexistent_dir/x.glb"), Error);
  SkeletalMotion empty = motion;
  empty.local_rotations.clear();
  empty.root_positions.clear();
  const auto dir = temp_dir("bad");
  try {
    write_glb(empty, dir / "empty.out");
    FAIL() << "a motion without frames was written";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::kBadInput);
    EXPECT_NE(std::string(e.what()).find("no frames"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "empty.out"));
}

}  // namespace
}  // namespace wheelpose::motion
