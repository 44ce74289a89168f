#include "generate/wheelchair_palette.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>

namespace wheelpose::generate {
namespace {

// The name of the shade nearest to `c` once the brightness jitter is undone, and how far
// (relative to the shade) it is.
std::string nearest_shade(const Eigen::Vector3f& c, const std::vector<ChairShade>& shades,
                          double* distance) {
  *distance = INFINITY;
  std::string name;
  for (const ChairShade& s : shades) {
    for (float k = 0.83f; k <= 1.17f; k += 0.01f) {
      const Eigen::Vector3f shade = s.colour * k;
      const double d = ((c - shade).cwiseAbs().array() / shade.array().max(0.01f)).maxCoeff();
      if (d < *distance) {
        *distance = d;
        name = s.name;
      }
    }
  }
  return name;
}

TEST(WheelchairPalette, ChairsAreMostlyNeutralWithDarkUpholstery) {
  RandomStream rng(11, {"chairs"});
  const int n = 4000;
  int neutral_frames = 0, black_upholstery = 0;
  for (int i = 0; i < n; ++i) {
    const ChairPaint paint = wheelchair_colours(rng, ChairColours::kPalette);
    double d = 0;
    const std::string frame = nearest_shade(paint[0], frame_shades(), &d);
    EXPECT_LT(d, 0.06) << i;
    neutral_frames +=
        frame == "black" || frame == "silver" || frame == "graphite" || frame == "white";
    const std::string upholstery = nearest_shade(paint[1], upholstery_shades(), &d);
    EXPECT_LT(d, 0.06) << i;
    black_upholstery += upholstery == "black";
    // Seat fabric is dark: no green or magenta slabs behind people's backs.
    EXPECT_LT(paint[1].maxCoeff(), 0.17f) << i;
    nearest_shade(paint[3], trim_shades(), &d);
    EXPECT_LT(d, 0.06) << i;
    EXPECT_EQ(paint[2].x(), paint[2].z());
    EXPECT_GE(paint[2].x(), 0.02f);
    EXPECT_LE(paint[2].x(), 0.12f);
  }
  // The weights: 64 % of frames neutral, 62 % of upholstery black.
  EXPECT_NEAR(neutral_frames / static_cast<double>(n), 0.64, 0.03);
  EXPECT_NEAR(black_upholstery / static_cast<double>(n), 0.62, 0.03);
}

TEST(WheelchairPalette, UniformIsTheEarlierDrawInItsOrder) {
  RandomStream a(3, {"chairs"}), b(3, {"chairs"});
  const ChairPaint paint = wheelchair_colours(a, ChairColours::kUniform);
  const float tyre = static_cast<float>(b.uniform(0.02, 0.12));
  auto next = [&b](double lo, double hi) {
    const float blue = static_cast<float>(b.uniform(lo, hi));
    const float green = static_cast<float>(b.uniform(lo, hi));
    const float red = static_cast<float>(b.uniform(lo, hi));
    return Eigen::Vector3f(red, green, blue);
  };
  const Eigen::Vector3f frame = next(0.05, 0.9), upholstery = next(0.02, 0.4),
                        trim = next(0.3, 0.8);
  EXPECT_EQ(paint[0], frame);
  EXPECT_EQ(paint[1], upholstery);
  EXPECT_EQ(paint[2], Eigen::Vector3f::Constant(tyre));
  EXPECT_EQ(paint[3], trim);
}

TEST(WheelchairPalette, TheSeedDecides) {
  RandomStream a(8, {"chairs"}), b(8, {"chairs"}), c(9, {"chairs"});
  const ChairPaint x = wheelchair_colours(a, ChairColours::kPalette);
  EXPECT_EQ(x, wheelchair_colours(b, ChairColours::kPalette));
  EXPECT_NE(x, wheelchair_colours(c, ChairColours::kPalette));
}

}  // namespace
}  // namespace wheelpose::generate
