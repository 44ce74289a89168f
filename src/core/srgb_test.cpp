#include "core/srgb.h"

#include <gtest/gtest.h>

namespace wheelpose {
namespace {

TEST(Srgb, RoundTripsAndMatchesTheStandard) {
  for (float c : {0.0f, 0.002f, 0.04f, 0.2f, 0.5f, 0.9f, 1.0f}) {
    EXPECT_NEAR(srgb_to_linear(linear_to_srgb(c)), c, 1e-5f);
  }
  EXPECT_NEAR(srgb_to_linear(0.5f), 0.21404f, 1e-5f);
}

TEST(Srgb, HexColoursDecodePerChannel) {
  const Eigen::Vector3f c = linear_from_srgb_hex(0x80ff00);
  EXPECT_NEAR(c.x(), srgb_to_linear(128 / 255.0f), 1e-7f);
  EXPECT_EQ(c.y(), 1.0f);
  EXPECT_EQ(c.z(), 0.0f);
}

}  // namespace
}  // namespace wheelpose
