#include "core/sampler.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

#include "core/error.h"

namespace wheelpose {

ScalarSampler ScalarSampler::constant(double value) {
  ScalarSampler s;
  s.kind_ = Kind::kConstant;
  s.a_ = value;
  return s;
}

ScalarSampler ScalarSampler::uniform(double lo, double hi) {
  WHEELPOSE_CHECK(lo <= hi);
  ScalarSampler s;
  s.kind_ = Kind::kUniform;
  s.a_ = lo;
  s.b_ = hi;
  return s;
}

ScalarSampler ScalarSampler::normal(double mean, double stddev, double min, double max) {
  WHEELPOSE_CHECK(stddev >= 0 && min <= max);
  ScalarSampler s;
  s.kind_ = Kind::kNormal;
  s.a_ = mean;
  s.b_ = stddev;
  s.min_ = min;
  s.max_ = max;
  return s;
}

ScalarSampler ScalarSampler::categorical(std::vector<double> values, std::vector<double> weights) {
  WHEELPOSE_CHECK(!values.empty() && values.size() == weights.size());
  ScalarSampler s;
  s.kind_ = Kind::kCategorical;
  s.values_ = std::move(values);
  s.cumulative_weights_.resize(weights.size());
  std::partial_sum(weights.begin(), weights.end(), s.cumulative_weights_.begin());
  return s;
}

ScalarSampler ScalarSampler::bernoulli(double p) {
  WHEELPOSE_CHECK(p >= 0 && p <= 1);
  ScalarSampler s;
  s.kind_ = Kind::kBernoulli;
  s.a_ = p;
  return s;
}

double ScalarSampler::sample(RandomStream& stream) const {
  switch (kind_) {
    case Kind::kConstant:
      return a_;
    case Kind::kUniform:
      return stream.uniform(a_, b_);
    case Kind::kNormal: {
      // Truncation by resampling keeps the shape inside the bounds; bounded effort, then clamp.
      for (int attempt = 0; attempt < 64; ++attempt) {
        double value = stream.normal(a_, b_);
        if (value >= min_ && value <= max_) return value;
      }
      return std::clamp(a_, min_, max_);
    }
    case Kind::kCategorical: {
      double target = stream.uniform01() * cumulative_weights_.back();
      auto it = std::upper_bound(cumulative_weights_.begin(), cumulative_weights_.end(), target);
      std::size_t index = std::min<std::size_t>(it - cumulative_weights_.begin(),
                                                values_.size() - 1);
      return values_[index];
    }
    case Kind::kBernoulli:
      return stream.bernoulli(a_) ? 1.0 : 0.0;
  }
  return a_;
}

double ScalarSampler::lower_bound() const {
  switch (kind_) {
    case Kind::kConstant:
    case Kind::kUniform:
      return a_;
    case Kind::kNormal:
      return min_;
    case Kind::kCategorical:
      return *std::min_element(values_.begin(), values_.end());
    case Kind::kBernoulli:
      return a_ >= 1.0 ? 1.0 : 0.0;
  }
  return a_;
}

double ScalarSampler::upper_bound() const {
  switch (kind_) {
    case Kind::kConstant:
      return a_;
    case Kind::kUniform:
      return b_;
    case Kind::kNormal:
      return max_;
    case Kind::kCategorical:
      return *std::max_element(values_.begin(), values_.end());
    case Kind::kBernoulli:
      return a_ > 0 ? 1.0 : 0.0;
  }
  return a_;
}

std::string ScalarSampler::describe() const {
  std::ostringstream out;
  switch (kind_) {
    case Kind::kConstant:
      out << "constant " << a_;
      break;
    case Kind::kUniform:
      out << "uniform [" << a_ << ", " << b_ << "]";
      break;
    case Kind::kNormal:
      out << "normal(mean " << a_ << ", std " << b_ << ")";
      break;
    case Kind::kCategorical:
      out << "categorical of " << values_.size() << " values";
      break;
    case Kind::kBernoulli:
      out << "bernoulli " << a_;
      break;
  }
  return out.str();
}

namespace {

std::vector<double> read_number_list(const ConfigNode& node) {
  if (!node.is_sequence()) node.fail("expected a list of numbers");
  std::vector<double> out;
  for (std::size_t i = 0; i < node.size(); ++i) out.push_back(node.element(i).as_double());
  return out;
}

ScalarSampler parse_sampler(const ConfigNode& node) {
  if (node.is_scalar()) return ScalarSampler::constant(node.as_double());
  if (!node.is_map() || node.size() != 1) {
    node.fail("expected a number or one of {constant, uniform, normal, categorical, bernoulli}");
  }
  const std::string kind = node.keys().front();
  const ConfigNode body = node.child(kind);
  if (kind == "constant") return ScalarSampler::constant(body.as_double());
  if (kind == "uniform") {
    auto range = read_number_list(body);
    if (range.size() != 2) body.fail("uniform needs [min, max]");
    if (range[0] > range[1]) body.fail("uniform min is greater than max");
    return ScalarSampler::uniform(range[0], range[1]);
  }
  if (kind == "normal") {
    double mean = body.get_double("mean", 0.0, -INFINITY, INFINITY);
    double stddev = body.get_double("std", 1.0, 0.0, INFINITY);
    double min = body.get_double("min", -INFINITY, -INFINITY, INFINITY);
    double max = body.get_double("max", INFINITY, -INFINITY, INFINITY);
    body.finish();
    if (min > max) body.fail("normal min is greater than max");
    return ScalarSampler::normal(mean, stddev, min, max);
  }
  if (kind == "categorical") {
    auto values = read_number_list(body.child("values"));
    std::vector<double> weights(values.size(), 1.0);
    if (auto w = body.optional_child("weights")) weights = read_number_list(*w);
    body.finish();
    if (values.empty()) body.fail("categorical needs at least one value");
    if (weights.size() != values.size()) body.fail("weights and values differ in length");
    double total = 0;
    for (double w : weights) {
      if (w < 0) body.fail("weights must not be negative");
      total += w;
    }
    if (total <= 0) body.fail("weights must not all be zero");
    return ScalarSampler::categorical(values, weights);
  }
  if (kind == "bernoulli") {
    double p = body.as_double();
    if (p < 0 || p > 1) body.fail("bernoulli probability must be in [0, 1]");
    return ScalarSampler::bernoulli(p);
  }
  node.fail("unknown distribution '" + kind +
            "' (expected constant, uniform, normal, categorical or bernoulli)");
}

}  // namespace

ScalarSampler ScalarSampler::from_config(const ConfigNode& node, double min, double max) {
  ScalarSampler sampler = parse_sampler(node);
  if (sampler.lower_bound() < min || sampler.upper_bound() > max) {
    std::ostringstream range;
    range << "[" << min << ", " << max << "]";
    node.fail(sampler.describe() + " can produce values outside " + range.str());
  }
  return sampler;
}

CartesianSampler CartesianSampler::from_config(const ConfigNode& node, double min, double max) {
  if (!node.is_map()) node.fail("expected {x: ..., y: ..., z: ...}");
  auto axis = [&](const char* name) {
    auto child = node.optional_child(name);
    return child ? ScalarSampler::from_config(*child, min, max) : ScalarSampler::constant(0.0);
  };
  CartesianSampler sampler(axis("x"), axis("y"), axis("z"));
  node.finish();
  return sampler;
}

Eigen::Vector3d CartesianSampler::sample(RandomStream& stream) const {
  const double x = x_.sample(stream);
  const double y = y_.sample(stream);
  const double z = z_.sample(stream);
  return {x, y, z};
}

EulerSampler EulerSampler::from_config(const ConfigNode& node) {
  return EulerSampler(CartesianSampler::from_config(node, -360.0, 360.0));
}

Eigen::Quaterniond EulerSampler::sample(RandomStream& stream) const {
  return euler_xyz_extrinsic(degrees_.sample(stream) * (M_PI / 180.0));
}

Eigen::Quaterniond euler_xyz_extrinsic(const Eigen::Vector3d& radians) {
  return Eigen::AngleAxisd(radians.z(), Eigen::Vector3d::UnitZ()) *
         Eigen::AngleAxisd(radians.y(), Eigen::Vector3d::UnitY()) *
         Eigen::AngleAxisd(radians.x(), Eigen::Vector3d::UnitX());
}

}  // namespace wheelpose
