#include "body/rigged_glb.h"

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <gtest/gtest.h>

#include <assimp/Importer.hpp>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>

#include "body/test_data.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "motion/library.h"
#include "motion/pipeline.h"

namespace wheelpose::body {
namespace {

using testing::body_data;
using testing::max_distance;
using testing::mean_distance;
namespace fs = std::filesystem;

fs::path temp_path(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / "wheelpose_rigged_glb_test";
  fs::create_directories(dir);
  return dir / name;
}

const motion::SkeletalMotion& test_clip() {
  static const motion::SkeletalMotion clip =
      motion::run_motion_pipeline(motion::library_clip("basketball_chest_pass", 3), {}).motion;
  return clip;
}

PersonSpec dressed_spec(std::uint64_t seed) {
  PersonSpec spec = sample_spec(seed);
  spec.limbs = {};
  spec.proxies = {"clothes/male_casualsuit01", "clothes/shoes01", "hair/bob01"};
  return spec;
}

// The glb as a reader plays it: joint world matrices from the animation's keys at `frame`
// (every key is a frame), times inverse bind matrices, blended by the vertex weights.
class SkinnedScene {
 public:
  explicit SkinnedScene(const fs::path& path) {
    scene_ = importer_.ReadFile(path.string(), 0);
    if (scene_ == nullptr) throw Error(importer_.GetErrorString());
  }
  const aiScene& scene() const { return *scene_; }
  const aiMesh* mesh(const std::string& name) const {
    for (unsigned m = 0; m < scene_->mNumMeshes; ++m)
      if (name == scene_->mMeshes[m]->mName.C_Str()) return scene_->mMeshes[m];
    return nullptr;
  }
  std::vector<Eigen::Vector3f> skinned(const aiMesh& mesh, std::size_t frame) const {
    std::map<std::string, aiMatrix4x4> world;
    collect(scene_->mRootNode, aiMatrix4x4(), frame, world);
    std::vector<Eigen::Vector3f> out(mesh.mNumVertices, Eigen::Vector3f::Zero());
    for (unsigned b = 0; b < mesh.mNumBones; ++b) {
      const aiBone& bone = *mesh.mBones[b];
      const aiMatrix4x4 m = world.at(bone.mName.C_Str()) * bone.mOffsetMatrix;
      for (unsigned w = 0; w < bone.mNumWeights; ++w) {
        const aiVertexWeight& vw = bone.mWeights[w];
        const aiVector3D p = m * mesh.mVertices[vw.mVertexId];
        out[vw.mVertexId] += vw.mWeight * Eigen::Vector3f(p.x, p.y, p.z);
      }
    }
    return out;
  }

 private:
  const aiNodeAnim* channel(const aiNode* node) const {
    const aiAnimation& animation = *scene_->mAnimations[0];
    for (unsigned c = 0; c < animation.mNumChannels; ++c)
      if (animation.mChannels[c]->mNodeName == node->mName) return animation.mChannels[c];
    return nullptr;
  }
  void collect(const aiNode* node, const aiMatrix4x4& parent, std::size_t frame,
               std::map<std::string, aiMatrix4x4>& world) const {
    aiMatrix4x4 local = node->mTransformation;
    if (const aiNodeAnim* anim = channel(node)) {
      aiVector3D scale, position;
      aiQuaternion rotation;
      local.Decompose(scale, rotation, position);
      auto key = [frame](unsigned n) { return std::min<std::size_t>(frame, n - 1); };
      if (anim->mNumPositionKeys > 0)
        position = anim->mPositionKeys[key(anim->mNumPositionKeys)].mValue;
      if (anim->mNumRotationKeys > 0)
        rotation = anim->mRotationKeys[key(anim->mNumRotationKeys)].mValue;
      local = aiMatrix4x4(aiVector3D(1, 1, 1), rotation, position);
    }
    const aiMatrix4x4 global = parent * local;
    world[node->mName.C_Str()] = global;
    for (unsigned c = 0; c < node->mNumChildren; ++c)
      collect(node->mChildren[c], global, frame, world);
  }
  Assimp::Importer importer_;
  const aiScene* scene_ = nullptr;
};

TEST(RiggedGlb, SkinnedBodyMatchesBuildPersonAtEveryTestedFrame) {
  const motion::SkeletalMotion& clip = test_clip();
  const PersonSpec spec = dressed_spec(5);
  const PersonAnimation animation = animate_person(body_data(), spec, clip);
  ASSERT_EQ(animation.frames.size(), clip.frame_count());
  const fs::path path = temp_path("person.glb");
  write_rigged_person_glb(animation, body_data(), path);
  const SkinnedScene glb(path);
  const aiScene& scene = glb.scene();
  ASSERT_EQ(scene.mNumAnimations, 1u);
  EXPECT_EQ(scene.mAnimations[0]->mNumChannels, body_data().rig().bones.size());
  const aiMesh* body = glb.mesh("body");
  ASSERT_NE(body, nullptr);
  EXPECT_EQ(body->mNumBones, 53u);
  // Weights of every vertex sum to 1.
  std::vector<float> sums(body->mNumVertices, 0.0f);
  for (unsigned b = 0; b < body->mNumBones; ++b)
    for (unsigned w = 0; w < body->mBones[b]->mNumWeights; ++w)
      sums[body->mBones[b]->mWeights[w].mVertexId] += body->mBones[b]->mWeights[w].mWeight;
  for (float s : sums) ASSERT_NEAR(s, 1.0f, 1e-6f);

  float worst_body = 0, worst_garment = 0, worst_garment_mean = 0;
  for (std::size_t frame : {std::size_t{0}, clip.frame_count() / 2, clip.frame_count() - 1}) {
    PersonSpec at_frame = spec;
    at_frame.pose = motion::global_rotations(clip, frame);
    const Person expected = build_person(body_data(), at_frame);
    worst_body = std::max(worst_body, max_distance(glb.skinned(*body, frame), expected.vertices));
    for (const Garment& g : expected.garments) {
      const aiMesh* mesh = glb.mesh(g.name.substr(g.name.find('/') + 1));
      ASSERT_NE(mesh, nullptr) << g.name;
      const std::vector<Eigen::Vector3f> skinned = glb.skinned(*mesh, frame);
      const float error = max_distance(skinned, g.vertices);
      std::printf("frame %zu %s: max %.1f mm, mean %.1f mm\n", frame, g.name.c_str(), error * 1e3,
                  mean_distance(skinned, g.vertices) * 1e3);
      worst_garment = std::max(worst_garment, error);
      worst_garment_mean = std::max(worst_garment_mean, mean_distance(skinned, g.vertices));
    }
  }
  std::printf("rigged glb vs build_person: body %.4f mm, garments %.1f mm\n", worst_body * 1e3,
              worst_garment * 1e3);
  EXPECT_LT(worst_body, 0.001f);
  // Garments are fitted to the posed triangles in build_person (offsets turn with them) and
  // skinned with blended weights here: a few millimetres on average, a few centimetres at worst.
  EXPECT_LT(worst_garment_mean, 0.01f);
  EXPECT_LT(worst_garment, 0.05f);
}

TEST(RiggedGlb, LimbCutsAndAidsFollowTheBones) {
  const motion::SkeletalMotion& clip = test_clip();
  PersonSpec spec = sample_spec(11);
  spec.limbs = {Cut::kNone, Cut::kAbove, Cut::kNone, Cut::kNone};
  spec.mobility_aid = MobilityAidType::kCane;
  const PersonAnimation animation = animate_person(body_data(), spec, clip);
  const fs::path path = temp_path("cane.glb");
  write_rigged_person_glb(animation, body_data(), path);
  const SkinnedScene glb(path);
  const std::size_t frame = clip.frame_count() - 1;
  PersonSpec at_frame = spec;
  at_frame.pose = motion::global_rotations(clip, frame);
  const Person expected = build_person(body_data(), at_frame);
  const std::vector<Eigen::Vector3f> body = glb.skinned(*glb.mesh("body"), frame);
  // Cap centres blend their rim's weights; the rest of the body is exact.
  const std::size_t caps = expected.cap_rims.size();
  ASSERT_GT(caps, 0u);
  const std::vector<Eigen::Vector3f> uncut(body.begin(), body.end() - static_cast<long>(caps));
  const std::vector<Eigen::Vector3f> want(expected.vertices.begin(),
                                          expected.vertices.end() - static_cast<long>(caps));
  EXPECT_LT(max_distance(uncut, want), 0.001f);
  EXPECT_LT(max_distance(body, expected.vertices), 0.01f);
  // The cane stays in the hand that holds it: its grip as near the wrist as at the first frame.
  const aiMesh* grip = glb.mesh("mobility_aid_hand_r_grips");
  ASSERT_NE(grip, nullptr);
  auto nearest = [](const std::vector<Eigen::Vector3f>& points, const Eigen::Vector3f& to) {
    float best = 1e9f;
    for (const auto& p : points) best = std::min(best, (p - to).norm());
    return best;
  };
  const float at_start = nearest(glb.skinned(*grip, 0), animation.person.coco[10]);
  EXPECT_NEAR(nearest(glb.skinned(*grip, frame), expected.coco[10]), at_start, 0.01f);
}

TEST(RiggedGlb, SameInputSameBytes) {
  const PersonAnimation animation = animate_person(body_data(), dressed_spec(2), test_clip());
  write_rigged_person_glb(animation, body_data(), temp_path("a.glb"));
  write_rigged_person_glb(animation, body_data(), temp_path("b.glb"));
  EXPECT_TRUE(read_file(temp_path("a.glb")) == read_file(temp_path("b.glb")));
}

TEST(RiggedGlb, ClipWithoutFramesIsBadInput) {
  motion::SkeletalMotion empty = test_clip();
  empty.local_rotations.clear();
  empty.root_positions.clear();
  try {
    animate_person(body_data(), dressed_spec(2), empty);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::kBadInput);
    EXPECT_NE(std::string(e.what()).find("no frames"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace wheelpose::body
