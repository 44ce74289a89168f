#include "motion/euler_curves.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/random.h"
#include "motion/test_support.h"

namespace wheelpose::motion {
namespace {

constexpr double kPi = std::numbers::pi;

Eigen::Quaterniond about(const Eigen::Vector3d& axis, double angle) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis.normalized()));
}

void expect_continuous_and_exact(const std::vector<Eigen::Quaterniond>& rotations,
                                 EulerOrder order) {
  const std::vector<Eigen::Vector3d> curves = continuous_euler(rotations, order);
  ASSERT_EQ(curves.size(), rotations.size());
  for (std::size_t k = 0; k < curves.size(); ++k) {
    EXPECT_LT(euler_rotation(curves[k], order).angularDistance(rotations[k]), 1e-9)
        << "key " << k << " order " << static_cast<int>(order);
    if (k > 0) {
      EXPECT_LE((curves[k] - curves[k - 1]).cwiseAbs().maxCoeff(), kPi)
          << "key " << k << " order " << static_cast<int>(order);
    }
  }
}

TEST(EulerCurves, OrdersComposeAsFbxDefinesThem) {
  // kXYZ applies X first: R = Rz·Ry·Rx; kZXY: R = Ry·Rx·Rz.
  const Eigen::Vector3d angles(0.3, -0.5, 1.1);
  const Eigen::Quaterniond rx = about(Eigen::Vector3d::UnitX(), 0.3);
  const Eigen::Quaterniond ry = about(Eigen::Vector3d::UnitY(), -0.5);
  const Eigen::Quaterniond rz = about(Eigen::Vector3d::UnitZ(), 1.1);
  EXPECT_LT(euler_rotation(angles, EulerOrder::kXYZ).angularDistance(rz * ry * rx), 1e-12);
  EXPECT_LT(euler_rotation(angles, EulerOrder::kZXY).angularDistance(ry * rx * rz), 1e-12);
  EXPECT_LT(euler_rotation(angles, EulerOrder::kYXZ).angularDistance(rz * rx * ry), 1e-12);
}

TEST(EulerCurves, RandomRotationsRoundTripInEveryOrder) {
  RandomStream stream(3, {"euler_curves"});
  std::vector<Eigen::Quaterniond> rotations;
  for (int i = 0; i < 300; ++i) {
    rotations.push_back(Eigen::Quaterniond(stream.normal(0, 1), stream.normal(0, 1),
                                           stream.normal(0, 1), stream.normal(0, 1))
                            .normalized());
  }
  for (int o = 0; o < 6; ++o) expect_continuous_and_exact(rotations, static_cast<EulerOrder>(o));
  // The first key starts in the principal range.
  const Eigen::Vector3d first = continuous_euler(rotations, EulerOrder::kXYZ).front();
  EXPECT_LE(std::abs(first.y()), kPi / 2 + 1e-12);
  EXPECT_LE(first.cwiseAbs().maxCoeff(), kPi + 1e-12);
}

TEST(EulerCurves, ATurnAcrossHalfCircleStaysContinuous) {
  // An elbow turning about X from 170° to 200° (= -160°): the curve goes on past 180° instead of
  // jumping to -180°, as the right_elbow X from -179.08° to 174.15° did.
  std::vector<Eigen::Quaterniond> rotations;
  for (int k = 0; k <= 30; ++k) {
    rotations.push_back(about(Eigen::Vector3d::UnitX(), (170.0 + k) * kPi / 180));
  }
  const std::vector<Eigen::Vector3d> curves = continuous_euler(rotations, EulerOrder::kXYZ);
  for (std::size_t k = 0; k < curves.size(); ++k) {
    EXPECT_NEAR(curves[k].x() * 180 / kPi, 170.0 + static_cast<double>(k), 1e-9) << k;
    EXPECT_NEAR(curves[k].y(), 0, 1e-9);
    EXPECT_NEAR(curves[k].z(), 0, 1e-9);
  }
  // A whole turn and more: the angle keeps growing.
  rotations.clear();
  for (int k = 0; k <= 80; ++k) rotations.push_back(about(Eigen::Vector3d::UnitY(), k * 0.1));
  const std::vector<Eigen::Vector3d> turning = continuous_euler(rotations, EulerOrder::kZXY);
  EXPECT_NEAR(turning.back().y(), 8.0, 1e-9);
  expect_continuous_and_exact(rotations, EulerOrder::kZXY);
}

TEST(EulerCurves, GimbalLockIsAvoidedByTheOrderChoice) {
  // An arm swinging forward to 90° about Y and twisting: XYZ (middle Y) passes through gimbal
  // lock, where linearly interpolated angles leave the rotation's path; the chosen order does not.
  std::vector<Eigen::Quaterniond> rotations;
  for (int k = 0; k <= 20; ++k) {
    const double s = k / 20.0;
    rotations.push_back(about(Eigen::Vector3d::UnitY(), -kPi / 2 * s) *
                        about(Eigen::Vector3d::UnitX(), 0.8 * s));
  }
  const double xyz_error =
      halfway_error(rotations, continuous_euler(rotations, EulerOrder::kXYZ), EulerOrder::kXYZ);
  const EulerOrder best = best_euler_order(rotations);
  const double best_error = halfway_error(rotations, continuous_euler(rotations, best), best);
  EXPECT_NE(best, EulerOrder::kXYZ);
  EXPECT_LT(best_error, 0.2 * xyz_error);
  EXPECT_LT(best_error, 1e-3);
}

TEST(EulerCurves, SyntheticMotionInterpolatesLikeSlerp) {
  // Every joint of a lively synthetic clip at 30 fps: halfway between keys, the angle curves in
  // the chosen order stay within 0.2° of the spherical interpolation.
  const SkeletalMotion motion = testing::synthetic_motion(90, 30, 11, 0.6);
  for (int joint = 0; joint < kJointCount; ++joint) {
    std::vector<Eigen::Quaterniond> rotations;
    for (const PoseRotations& frame : motion.local_rotations) rotations.push_back(frame[joint]);
    const EulerOrder order = best_euler_order(rotations);
    expect_continuous_and_exact(rotations, order);
    const double error = halfway_error(rotations, continuous_euler(rotations, order), order);
    EXPECT_LT(error, 0.2 * kPi / 180) << joint_name(joint);
  }
}

}  // namespace
}  // namespace wheelpose::motion
