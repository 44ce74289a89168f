#pragma once
// Distributions as written in configs and in the paper's randomizer table:
//   constant: 5                      uniform: [5, 50]
//   normal: {mean: 0, std: 1, min: -2, max: 2}   (min/max optional: truncation by resampling)
//   categorical: {values: [a, b], weights: [1, 3]}
//   bernoulli: 0.8
// plus vector forms: Cartesian {x: D, y: D, z: D} and Euler angles in degrees {x: D, y: D, z: D}.

#include <Eigen/Geometry>
#include <memory>
#include <string>
#include <vector>

#include "core/config.h"
#include "core/random.h"

namespace wheelpose {

class ScalarSampler {
 public:
  static ScalarSampler constant(double value);
  static ScalarSampler uniform(double lo, double hi);
  static ScalarSampler normal(double mean, double stddev, double min = -INFINITY,
                              double max = INFINITY);
  static ScalarSampler categorical(std::vector<double> values, std::vector<double> weights);
  static ScalarSampler bernoulli(double p);  // yields 1.0 or 0.0

  // Reads one of the forms above; bare numbers are constants. Values must lie in [min, max].
  static ScalarSampler from_config(const ConfigNode& node, double min = -INFINITY,
                                   double max = INFINITY);

  double sample(RandomStream& stream) const;
  double lower_bound() const;  // smallest value it can return
  double upper_bound() const;  // largest value it can return
  std::string describe() const;

 private:
  enum class Kind { kConstant, kUniform, kNormal, kCategorical, kBernoulli };
  Kind kind_ = Kind::kConstant;
  double a_ = 0, b_ = 0, min_ = -INFINITY, max_ = INFINITY;
  std::vector<double> values_, cumulative_weights_;
};

class CartesianSampler {
 public:
  CartesianSampler(ScalarSampler x, ScalarSampler y, ScalarSampler z)
      : x_(std::move(x)), y_(std::move(y)), z_(std::move(z)) {}
  static CartesianSampler from_config(const ConfigNode& node, double min = -INFINITY,
                                      double max = INFINITY);
  Eigen::Vector3d sample(RandomStream& stream) const;

 private:
  ScalarSampler x_, y_, z_;
};

// Euler angles in degrees, applied extrinsically in x, y, z order (R = Rz·Ry·Rx), the
// convention of scipy's "xyz" and of the paper's noise.
class EulerSampler {
 public:
  explicit EulerSampler(CartesianSampler degrees) : degrees_(std::move(degrees)) {}
  static EulerSampler from_config(const ConfigNode& node);
  Eigen::Quaterniond sample(RandomStream& stream) const;

 private:
  CartesianSampler degrees_;
};

// R = Rz(z)·Ry(y)·Rx(x), angles in radians.
Eigen::Quaterniond euler_xyz_extrinsic(const Eigen::Vector3d& radians);

}  // namespace wheelpose
