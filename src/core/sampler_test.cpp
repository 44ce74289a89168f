#include "core/sampler.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"

namespace wheelpose {
namespace {

ScalarSampler parse(const std::string& yaml, double min = -INFINITY, double max = INFINITY) {
  ConfigNode root = ConfigNode::load_string(yaml, "test.yaml");
  return ScalarSampler::from_config(root.child("d"), min, max);
}

TEST(ScalarSampler, ParsesEveryForm) {
  RandomStream stream(1, {"s"});
  EXPECT_EQ(parse("d: 4.5").sample(stream), 4.5);
  EXPECT_EQ(parse("d: {constant: 2}").sample(stream), 2.0);
  double u = parse("d: {uniform: [5, 50]}").sample(stream);
  EXPECT_GE(u, 5);
  EXPECT_LT(u, 50);
  double n = parse("d: {normal: {mean: 0, std: 1, min: -0.5, max: 0.5}}").sample(stream);
  EXPECT_LE(std::abs(n), 0.5);
  double c = parse("d: {categorical: {values: [1, 2, 3], weights: [0, 1, 0]}}").sample(stream);
  EXPECT_EQ(c, 2.0);
  double b = parse("d: {bernoulli: 1}").sample(stream);
  EXPECT_EQ(b, 1.0);
}

TEST(ScalarSampler, CategoricalFollowsWeights) {
  auto sampler = ScalarSampler::categorical({10, 20}, {1, 3});
  RandomStream stream(2, {"cat"});
  int twenties = 0;
  for (int i = 0; i < 40000; ++i) twenties += sampler.sample(stream) == 20;
  EXPECT_NEAR(twenties / 40000.0, 0.75, 0.01);
}

TEST(ScalarSampler, BernoulliFollowsProbability) {
  auto sampler = ScalarSampler::bernoulli(0.8);
  RandomStream stream(2, {"b"});
  int ones = 0;
  for (int i = 0; i < 40000; ++i) ones += sampler.sample(stream) == 1.0;
  EXPECT_NEAR(ones / 40000.0, 0.8, 0.01);
}

TEST(ScalarSampler, ErrorsNameFileLineAndKey) {
  try {
    parse("a: 1\nd: {uniform: [50, 5]}");
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "test.yaml:2: key 'd.uniform': uniform min is greater than max");
  }
  EXPECT_THROW(parse("d: {gaussian: 1}"), Error);
  EXPECT_THROW(parse("d: {uniform: [1]}"), Error);
  EXPECT_THROW(parse("d: {bernoulli: 1.5}"), Error);
  EXPECT_THROW(parse("d: {normal: {mean: 0, sd: 1}}"), Error);  // unknown key
  EXPECT_THROW(parse("d: {uniform: [0, 100]}", 0, 50), Error);  // out of allowed range
}

TEST(CartesianAndEuler, SampleEachAxisIndependently) {
  ConfigNode root = ConfigNode::load_string(
      "p: {x: {uniform: [-5, 5]}, y: 2, z: {uniform: [10, 20]}}\nr: {y: 90}", "t.yaml");
  auto position = CartesianSampler::from_config(root.child("p"));
  RandomStream stream(4, {"c"});
  Eigen::Vector3d p = position.sample(stream);
  EXPECT_GE(p.x(), -5);
  EXPECT_LT(p.x(), 5);
  EXPECT_EQ(p.y(), 2);
  EXPECT_GE(p.z(), 10);
  auto rotation = EulerSampler::from_config(root.child("r")).sample(stream);
  Eigen::Vector3d x_axis = rotation * Eigen::Vector3d::UnitX();
  EXPECT_NEAR(x_axis.z(), -1.0, 1e-12);  // +90 degrees about Y takes +X to -Z
}

TEST(EulerXyzExtrinsic, AppliesXThenYThenZ) {
  // Extrinsic xyz: rotate about world X first. (90, 90, 0) degrees takes +Y to +Z then to +Z.
  auto q = euler_xyz_extrinsic(Eigen::Vector3d(M_PI / 2, M_PI / 2, 0));
  Eigen::Vector3d y = q * Eigen::Vector3d::UnitY();
  EXPECT_NEAR(y.x(), 1.0, 1e-12);  // X: +Y -> +Z, then Y(90): +Z -> +X
}

}  // namespace
}  // namespace wheelpose
