#include "scene/blackbody.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>

namespace wheelpose::scene {
namespace {

// CIE xy chromaticity of a linear sRGB colour (IEC 61966-2-1's RGB to XYZ matrix).
Eigen::Vector2d chromaticity(const Eigen::Vector3f& rgb) {
  Eigen::Matrix3d to_xyz;
  to_xyz << 0.4124, 0.3576, 0.1805, 0.2126, 0.7152, 0.0722, 0.0193, 0.1192, 0.9505;
  const Eigen::Vector3d xyz = to_xyz * rgb.cast<double>();
  return xyz.head<2>() / xyz.sum();
}

// CIE illuminant A is a black body at 2,856 K: x = 0.4476, y = 0.4074 (CIE 15:2004).
TEST(Blackbody, IlluminantAIsOnTheLocus) {
  const Eigen::Vector2d xy = chromaticity(blackbody_rgb(2856));
  EXPECT_NEAR(xy.x(), 0.4476, 0.002);
  EXPECT_NEAR(xy.y(), 0.4074, 0.002);
}

// Published Planckian chromaticities (Wyszecki & Stiles) at 4,000 K and 10,000 K.
TEST(Blackbody, MatchesThePlanckianLocus) {
  EXPECT_NEAR(chromaticity(blackbody_rgb(4000)).x(), 0.3805, 0.002);
  EXPECT_NEAR(chromaticity(blackbody_rgb(4000)).y(), 0.3768, 0.002);
  EXPECT_NEAR(chromaticity(blackbody_rgb(10000)).x(), 0.2807, 0.002);
  EXPECT_NEAR(chromaticity(blackbody_rgb(10000)).y(), 0.2883, 0.002);
}

TEST(Blackbody, WarmIsRedCoolIsBlueAndTheBrightestChannelIsOne) {
  double last_blue_over_red = 0;
  for (double kelvin = 1700; kelvin <= 25000; kelvin *= 1.1) {
    const Eigen::Vector3f rgb = blackbody_rgb(kelvin);
    EXPECT_FLOAT_EQ(rgb.maxCoeff(), 1.0f) << kelvin;
    EXPECT_GE(rgb.minCoeff(), 0.0f) << kelvin;
    const double blue_over_red = rgb.z() / rgb.x();
    // Below about 1,900 K blue lies outside the sRGB gamut (clipped to 0).
    if (blue_over_red > 0) {
      EXPECT_GT(blue_over_red, last_blue_over_red) << kelvin;
    }
    last_blue_over_red = blue_over_red;
  }
  EXPECT_EQ(blackbody_rgb(2700).x(), 1.0f);  // a warm bulb: red brightest, blue a tenth
  EXPECT_NEAR(blackbody_rgb(2700).z(), 0.10, 0.01);
  EXPECT_EQ(blackbody_rgb(500), blackbody_rgb(kMinColourTemperature));  // clamped to the fit
}

}  // namespace
}  // namespace wheelpose::scene
