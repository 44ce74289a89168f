#include "motion/plausibility.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <numbers>

namespace wheelpose::motion {
namespace {

using Eigen::Vector3d;
using ::testing::HasSubstr;

// Seated, upright, upper arms hanging slightly forward, forearms resting forward over the lap.
Pose neutral_pose() {
  Pose p;
  p[kPelvis] = {0, 0.5, 0};
  p[kLeftHip] = {0.1, 0.5, 0};
  p[kRightHip] = {-0.1, 0.5, 0};
  p[kLeftKnee] = {0.1, 0.5, 0.4};
  p[kRightKnee] = {-0.1, 0.5, 0.4};
  p[kLeftAnkle] = {0.1, 0.09, 0.4};
  p[kRightAnkle] = {-0.1, 0.09, 0.4};
  p[kLeftToe] = {0.1, 0.09, 0.54};
  p[kRightToe] = {-0.1, 0.09, 0.54};
  p[kSpine] = {0, 0.61, 0};
  p[kChest] = {0, 0.74, 0};
  p[kUpperChest] = {0, 0.80, 0};
  p[kNeckBase] = {0, 0.95, 0};
  p[kHeadBase] = {0, 1.02, 0};
  p[kHeadTop] = {0, 1.22, 0};
  p[kLeftClavicle] = {0.03, 0.95, 0};
  p[kRightClavicle] = {-0.03, 0.95, 0};
  p[kLeftShoulder] = {0.15, 0.95, 0};
  p[kRightShoulder] = {-0.15, 0.95, 0};
  p[kLeftElbow] = {0.15, 0.68, 0};
  p[kRightElbow] = {-0.15, 0.68, 0};
  p[kLeftWrist] = {0.15, 0.68, 0.25};
  p[kRightWrist] = {-0.15, 0.68, 0.25};
  return p;
}

// Problems of a clip that holds `pose` for three frames.
std::vector<std::string> problems_of(const Pose& pose) {
  return plausibility_problems({pose, pose, pose});
}

// Rotates the joints above the spine joint about `axis` through the spine joint.
Pose rotate_upper_body(Pose p, const Vector3d& axis, double degrees) {
  const Eigen::AngleAxisd r(degrees * std::numbers::pi / 180.0, axis);
  const Vector3d centre = p[kSpine];
  for (int j : {kChest, kUpperChest, kNeckBase, kHeadBase, kHeadTop, kLeftClavicle, kRightClavicle,
                kLeftShoulder, kRightShoulder, kLeftElbow, kRightElbow, kLeftWrist, kRightWrist}) {
    p[j] = centre + r * (p[j] - centre);
  }
  return p;
}

bool any_contains(const std::vector<std::string>& problems, const std::string& text) {
  for (const std::string& p : problems) {
    if (p.find(text) != std::string::npos) return true;
  }
  return false;
}

TEST(Plausibility, NeutralSeatedPoseIsClean) {
  EXPECT_THAT(problems_of(neutral_pose()), ::testing::IsEmpty());
}

TEST(Plausibility, MeasuresHandBuiltAngles) {
  const PoseAngles a = measure_pose_angles(neutral_pose());
  EXPECT_NEAR(a.elbow_flexion[0], 90.0, 1e-9);
  EXPECT_NEAR(a.elbow_flexion[1], 90.0, 1e-9);
  EXPECT_NEAR(a.humeral_rotation[0], 0.0, 1e-9);  // forearm straight ahead of a hanging arm
  EXPECT_NEAR(a.arm_extension[0], 0.0, 1e-9);
  EXPECT_NEAR(a.clavicle_elevation[1], 0.0, 1e-9);
  EXPECT_NEAR(a.neck_flexion, 0.0, 1e-9);
  EXPECT_NEAR(a.trunk_twist, 0.0, 1e-9);

  // Left forearm turned in across the belly: 90 degrees of internal rotation.
  Pose p = neutral_pose();
  p[kLeftWrist] = p[kLeftElbow] + Vector3d(-0.25, 0, 0.0);
  p[kLeftElbow].z() = 0.15;  // keep the forearm in front of the trunk
  p[kLeftWrist].z() = 0.15;
  EXPECT_NEAR(measure_pose_angles(p).humeral_rotation[0], 90.0, 1e-6);

  // Upper body turned 30 degrees to the left about the vertical, head nodding 20 degrees.
  Pose twisted = rotate_upper_body(neutral_pose(), Vector3d::UnitY(), 30.0);
  EXPECT_NEAR(measure_pose_angles(twisted).trunk_twist, 30.0, 1e-9);
  Pose nod = neutral_pose();
  const double r = 20.0 * std::numbers::pi / 180.0;
  nod[kHeadTop] = nod[kHeadBase] + 0.2 * Vector3d(0, std::cos(r), std::sin(r));
  EXPECT_NEAR(measure_pose_angles(nod).neck_flexion, 20.0, 1e-9);
}

TEST(Plausibility, FlagsElbowFlexionBeyondRange) {
  Pose p = neutral_pose();
  // Forearm folded to 170 degrees: points back up along the upper arm, tilted forward by 10.
  const double r = 10.0 * std::numbers::pi / 180.0;
  p[kLeftWrist] = p[kLeftElbow] + 0.25 * Vector3d(0, std::cos(r), std::sin(r));
  const auto problems = problems_of(p);
  ASSERT_FALSE(problems.empty());
  EXPECT_THAT(problems[0], HasSubstr("left elbow flexion 170.0 deg beyond 155"));
  EXPECT_THAT(problems[0], HasSubstr("at frame 0 (3 of 3 frames)"));
}

TEST(Plausibility, FlagsElbowHyperextension) {
  Pose p = neutral_pose();
  // Arm hanging, forearm bent backwards: impossible without twisting the humerus by 180.
  p[kRightWrist] = p[kRightElbow] + Vector3d(0, -0.02, -0.25);
  EXPECT_TRUE(any_contains(problems_of(p), "right elbow bends the wrong way"));
}

TEST(Plausibility, FlagsShoulderExtensionAndAdduction) {
  Pose back = neutral_pose();
  const double r = 75.0 * std::numbers::pi / 180.0;
  back[kLeftElbow] = back[kLeftShoulder] + 0.27 * Vector3d(0, -std::cos(r), -std::sin(r));
  back[kLeftWrist] = back[kLeftElbow] + 0.25 * Vector3d(0, -std::cos(r), -std::sin(r));
  EXPECT_TRUE(any_contains(problems_of(back), "left shoulder extension 75.0 deg beyond 60"));

  Pose across = neutral_pose();
  const Vector3d d = Vector3d(-0.94, 0.0, 0.34).normalized();
  across[kRightElbow] = across[kRightShoulder] + 0.27 * Vector3d(-d.x(), d.y(), d.z());
  across[kRightWrist] = across[kRightElbow] + 0.25 * Vector3d(0, 0, 1);
  EXPECT_TRUE(any_contains(problems_of(across), "right shoulder horizontal adduction"));
}

TEST(Plausibility, FlagsClavicleElevation) {
  Pose p = neutral_pose();
  const double r = 60.0 * std::numbers::pi / 180.0;
  p[kLeftShoulder] = p[kLeftClavicle] + 0.12 * Vector3d(std::cos(r), std::sin(r), 0);
  p[kLeftElbow] = p[kLeftShoulder] + Vector3d(0, -0.27, 0);
  p[kLeftWrist] = p[kLeftElbow] + Vector3d(0, 0, 0.25);
  EXPECT_TRUE(any_contains(problems_of(p), "left clavicle elevation 60.0 deg"));
}

TEST(Plausibility, FlagsNeckBeyondRange) {
  Pose p = neutral_pose();
  const double r = 65.0 * std::numbers::pi / 180.0;
  p[kHeadTop] = p[kHeadBase] + 0.2 * Vector3d(0, std::cos(r), -std::sin(r));
  EXPECT_TRUE(any_contains(problems_of(p), "neck flexion -65.0 deg"));
  Pose tilt = neutral_pose();
  tilt[kHeadTop] = tilt[kHeadBase] + 0.2 * Vector3d(std::sin(r), std::cos(r), 0);
  EXPECT_TRUE(any_contains(problems_of(tilt), "neck lateral bend 65.0 deg"));
}

TEST(Plausibility, FlagsTrunkBeyondRange) {
  EXPECT_TRUE(any_contains(problems_of(rotate_upper_body(neutral_pose(), Vector3d::UnitY(), 60)),
                           "trunk twist 60.0 deg"));
  EXPECT_TRUE(any_contains(problems_of(rotate_upper_body(neutral_pose(), Vector3d::UnitX(), -40)),
                           "trunk flexion -40.0 deg"));
  EXPECT_TRUE(any_contains(problems_of(rotate_upper_body(neutral_pose(), Vector3d::UnitZ(), 50)),
                           "trunk lateral bend"));
  // Within range: 30 degrees forward, 20 twist.
  EXPECT_THAT(problems_of(rotate_upper_body(neutral_pose(), Vector3d::UnitX(), 30)),
              ::testing::IsEmpty());
}

TEST(Plausibility, FlagsBoneLengthChange) {
  Pose stretched = neutral_pose();
  stretched[kLeftWrist] = stretched[kLeftElbow] + Vector3d(0, 0, 0.30);
  const auto problems = plausibility_problems({neutral_pose(), neutral_pose(), stretched});
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_EQ(problems[0],
            "bone left_elbow-left_wrist changes length from 0.250 m to 0.300 m at frame 2 "
            "(1 of 3 frames)");
  // A 3 mm change is within tolerance.
  Pose slight = neutral_pose();
  slight[kLeftWrist] = slight[kLeftElbow] + Vector3d(0, 0, 0.253);
  EXPECT_THAT(plausibility_problems({neutral_pose(), slight}), ::testing::IsEmpty());
}

TEST(Plausibility, FlagsForearmThroughTrunkButAllowsTouchingIt) {
  Pose through = neutral_pose();
  through[kLeftElbow] = {0.15, 0.70, 0.02};
  through[kLeftWrist] = {-0.09, 0.72, 0.0};
  EXPECT_TRUE(any_contains(problems_of(through), "left forearm passes through the trunk"));

  // Hand resting on the belly surface, 11 cm in front of the spine axis: fine.
  Pose touching = neutral_pose();
  touching[kLeftElbow] = {0.16, 0.69, 0.09};
  touching[kLeftWrist] = touching[kLeftElbow] + 0.25 * Vector3d(-0.95, 0.0, 0.1).normalized();
  ASSERT_GT(touching[kLeftWrist].z(), 0.1);
  EXPECT_THAT(problems_of(touching), ::testing::IsEmpty());
}

TEST(Plausibility, FlagsArmThroughHead) {
  Pose p = neutral_pose();
  p[kRightElbow] = p[kRightShoulder] + 0.27 * Vector3d(0.3, 0.95, 0.0).normalized();
  p[kRightWrist] = p[kRightElbow] + 0.25 * Vector3d(1, 0, 0);
  EXPECT_TRUE(any_contains(problems_of(p), "right forearm passes through the head"));
}

TEST(Plausibility, FlagsNonFinitePositions) {
  Pose p = neutral_pose();
  p[kHeadTop].x() = std::numeric_limits<double>::quiet_NaN();
  const auto problems = plausibility_problems({neutral_pose(), p});
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_THAT(problems[0], HasSubstr("non-finite joint position at frame 1"));
}

TEST(Plausibility, EmptyClipHasNoProblems) {
  EXPECT_THAT(plausibility_problems({}), ::testing::IsEmpty());
}

}  // namespace
}  // namespace wheelpose::motion
