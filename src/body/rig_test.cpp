#include "body/rig.h"

#include <gtest/gtest.h>

#include <cmath>

#include "body/test_data.h"
#include "motion/skeleton.h"

namespace wheelpose::body {
namespace {

using testing::body_data;

TEST(Rig, JointsFollowTheMorphedMesh) {
  const BodyData& data = body_data();
  MacroParams tall, short_;
  tall.height = 1.0;
  short_.height = 0.0;
  const BoneFrames a = bone_positions(data.rig(), data.model().morph(tall));
  const BoneFrames b = bone_positions(data.rig(), data.model().morph(short_));
  const int head = data.rig().bone("head"), foot = data.rig().bone("foot_l");
  // Joint = mean of its cube's vertices, so a taller body has a longer head-to-ankle span.
  EXPECT_GT(a.head[head].y() - a.head[foot].y(), b.head[head].y() - b.head[foot].y() + 0.05f);
  // Hand-checked: the left thigh head is on the subject's left (+X), below the pelvis head.
  const int thigh = data.rig().bone("thigh_l"), pelvis = data.rig().bone("pelvis");
  EXPECT_GT(a.head[thigh].x(), 0.05f);
  EXPECT_LT(a.head[thigh].y(), a.head[pelvis].y() + 0.02f);
  // Equals the mean of the cube vertices computed directly.
  const auto v = data.model().morph(tall);
  Eigen::Vector3f mean = Eigen::Vector3f::Zero();
  const auto& cube = data.model().base().group_vertices.at("joint-l-knee");
  for (int i : cube) mean += v[i];
  mean /= static_cast<float>(cube.size());
  EXPECT_LT((a.head[data.rig().bone("calf_l")] - mean).norm(), 1e-6f);
}

TEST(Rig, BonesOrderedParentsFirstWithNormalisedWeights) {
  const Rig& rig = body_data().rig();
  EXPECT_EQ(rig.bones.size(), 53u);
  for (std::size_t b = 0; b < rig.bones.size(); ++b)
    EXPECT_LT(rig.bones[b].parent, static_cast<int>(b));
  for (const auto& w : rig.influence_weight) {
    EXPECT_NEAR(w[0] + w[1] + w[2] + w[3], 1.0f, 1e-5f);
  }
}

TEST(Skinning, BindPoseReproducesRestMesh) {
  const BodyData& data = body_data();
  MacroParams p;
  p.weight = 0.8;
  const auto rest = data.model().morph(p);
  const BoneFrames bones = bone_positions(data.rig(), rest);
  const auto out = skin(data.rig(), bones, bind_pose(data.rig()), rest);
  float worst = 0;
  for (std::size_t i = 0; i < rest.size(); ++i) worst = std::max(worst, (out[i] - rest[i]).norm());
  EXPECT_LT(worst, 1e-6f);
}

TEST(Skinning, RigidRotationOfEveryBoneRotatesTheMesh) {
  const BodyData& data = body_data();
  const auto rest = data.model().morph(MacroParams{});
  const BoneFrames bones = bone_positions(data.rig(), rest);
  RigPose pose = bind_pose(data.rig());
  const Eigen::Quaternionf q(Eigen::AngleAxisf(0.7f, Eigen::Vector3f::UnitY()));
  for (auto& r : pose.rotation) r = q;
  const auto out = skin(data.rig(), bones, pose, rest);
  const Eigen::Vector3f root = bones.head[0];
  float worst = 0;
  for (std::size_t i = 0; i < rest.size(); ++i) {
    worst = std::max(worst, (out[i] - (root + q * (rest[i] - root))).norm());
  }
  EXPECT_LT(worst, 1e-5f);
}

double angle_deg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * 180.0 / M_PI;
}

TEST(Retarget, PosedBonesFollowClipDirectionsWithin2Degrees) {
  const BodyData& data = body_data();
  const auto rest = data.model().morph(MacroParams{});
  const BoneFrames bones = bone_positions(data.rig(), rest);
  // A clip pose with every mapped joint turned: arms forward/up, trunk bent and twisted.
  motion::PoseRotations g;
  for (int j = 0; j < motion::kJointCount; ++j) {
    const Eigen::Vector3d axis = Eigen::Vector3d(std::sin(j), std::cos(2.0 * j), 0.5).normalized();
    g[j] = Eigen::Quaterniond(Eigen::AngleAxisd(0.1 + 0.07 * j, axis));
  }
  const RigPose pose = retarget(data.rig(), bones, g);
  const BoneFrames posed = pose_bones(data.rig(), bones, pose);
  const motion::Pose joints = skeleton_joints(data.rig(), posed);
  int checked = 0;
  for (const BoneMapping& m : bone_mapping()) {
    if (m.clip_parent == m.clip_child) continue;
    const Eigen::Vector3d expected = g[m.clip_parent] * motion::rest_direction(m.clip_child);
    const Eigen::Vector3d got = joints[m.clip_child] - joints[m.clip_parent];
    EXPECT_LT(angle_deg(expected, got), 2.0) << m.rig_bone;
    ++checked;
  }
  EXPECT_EQ(checked, 16);
  EXPECT_LT(joints[motion::kPelvis].norm(), 1e-6);  // pelvis on the origin, like the clips
}

}  // namespace
}  // namespace wheelpose::body
