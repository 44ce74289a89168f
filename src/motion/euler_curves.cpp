#include "motion/euler_curves.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace wheelpose::motion {

namespace {

constexpr double kPi = std::numbers::pi;

// Axis indices in the order they are applied.
std::array<int, 3> axes(EulerOrder order) {
  static constexpr std::array<std::array<int, 3>, 6> kAxes = {{
      {0, 1, 2},  // XYZ
      {0, 2, 1},  // XZY
      {1, 2, 0},  // YZX
      {1, 0, 2},  // YXZ
      {2, 0, 1},  // ZXY
      {2, 1, 0},  // ZYX
  }};
  return kAxes[static_cast<int>(order)];
}

Eigen::Vector3d euler_angles(const Eigen::Quaterniond& q, EulerOrder order) {
  const auto [first, second, third] = axes(order);
  // Eigen's angles (a, b, c) give R = R_third(a) · R_second(b) · R_first(c).
  const Eigen::Vector3d e = q.normalized().toRotationMatrix().eulerAngles(third, second, first);
  Eigen::Vector3d xyz;
  xyz[third] = e[0];
  xyz[second] = e[1];
  xyz[first] = e[2];
  return xyz;
}

// The other angle set of the same rotation: outer angles + 180°, middle 180° − itself.
Eigen::Vector3d other_solution(const Eigen::Vector3d& xyz, EulerOrder order) {
  const auto [first, second, third] = axes(order);
  Eigen::Vector3d other = xyz;
  other[first] += kPi;
  other[second] = kPi - other[second];
  other[third] += kPi;
  return other;
}

double wrap_near(double angle, double target) {
  return angle + 2 * kPi * std::round((target - angle) / (2 * kPi));
}

}  // namespace

Eigen::Quaterniond euler_rotation(const Eigen::Vector3d& angles, EulerOrder order) {
  const auto [first, second, third] = axes(order);
  auto about = [&](int axis) {
    return Eigen::Quaterniond(Eigen::AngleAxisd(angles[axis], Eigen::Vector3d::Unit(axis)));
  };
  return about(third) * about(second) * about(first);
}

std::vector<Eigen::Vector3d> continuous_euler(const std::vector<Eigen::Quaterniond>& rotations,
                                              EulerOrder order) {
  const int middle = axes(order)[1];
  std::vector<Eigen::Vector3d> curves;
  curves.reserve(rotations.size());
  for (const Eigen::Quaterniond& q : rotations) {
    const Eigen::Vector3d a = euler_angles(q, order);
    const Eigen::Vector3d b = other_solution(a, order);
    if (curves.empty()) {
      Eigen::Vector3d first = std::abs(wrap_near(a[middle], 0)) <= kPi / 2 ? a : b;
      for (int i = 0; i < 3; ++i) first[i] = wrap_near(first[i], 0);
      curves.push_back(first);
      continue;
    }
    const Eigen::Vector3d previous = curves.back();
    const Eigen::Vector3d candidates[2] = {a, b};
    Eigen::Vector3d best;
    double best_cost = 0;
    for (int c = 0; c < 2; ++c) {
      Eigen::Vector3d near = candidates[c];
      for (int i = 0; i < 3; ++i) near[i] = wrap_near(near[i], previous[i]);
      const double cost = (near - previous).cwiseAbs().sum();
      if (c == 0 || cost < best_cost) {
        best = near;
        best_cost = cost;
      }
    }
    curves.push_back(best);
  }
  return curves;
}

double halfway_error(const std::vector<Eigen::Quaterniond>& rotations,
                     const std::vector<Eigen::Vector3d>& curves, EulerOrder order) {
  double worst = 0;
  for (std::size_t k = 0; k + 1 < rotations.size(); ++k) {
    const Eigen::Quaterniond spherical = rotations[k].slerp(0.5, rotations[k + 1]);
    const Eigen::Quaterniond linear = euler_rotation(0.5 * (curves[k] + curves[k + 1]), order);
    worst = std::max(worst, spherical.angularDistance(linear));
  }
  return worst;
}

EulerOrder best_euler_order(const std::vector<Eigen::Quaterniond>& rotations) {
  EulerOrder best = EulerOrder::kXYZ;
  double best_error = 0;
  for (int o = 0; o < 6; ++o) {
    const auto order = static_cast<EulerOrder>(o);
    const double error = halfway_error(rotations, continuous_euler(rotations, order), order);
    if (o == 0 || error < best_error) {
      best = order;
      best_error = error;
    }
  }
  return best;
}

}  // namespace wheelpose::motion
