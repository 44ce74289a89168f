#include "generate/wheelchair_palette.h"

#include <gtest/gtest.h>

#include <limits>
#include <string>

namespace wheelpose::generate {
namespace {

// The name of the shade nearest to `c` once the brightness jitter is undone, and how far
// (relative to the shade) it is.
std::string nearest_shade(const Eigen::Vector3f& c, const std::vector<ChairShade>& shades,
                          double* distance) {
  *distance = std::numeric_limits<double>::infinity();
  std::string name;
  for (const ChairShade& s : shades) {
    for (int percent = 83; percent <= 117; ++percent) {
      const Eigen::Vector3f shade = s.colour * (percent / 100.0f);
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
    EXPECT_EQ(paint[2], Eigen::Vector3f::Constant(paint[2].x()));
    EXPECT_GE(paint[2].x(), 0.02f);
    EXPECT_LE(paint[2].x(), 0.12f);
  }
  // The weights: 64 % of frames neutral, 62 % of upholstery black.
  EXPECT_NEAR(neutral_frames / static_cast<double>(n), 0.64, 0.03);
  EXPECT_NEAR(black_upholstery / static_cast<double>(n), 0.62, 0.03);
}

// Golden values: the Wheelchair randomizer's colours() as it was at 7ff40fa, compiled with GCC
// and run on this stream, so `colours: uniform` keeps drawing the very same chairs.
TEST(WheelchairPalette, UniformIsTheEarlierDraw) {
  RandomStream rng(3, {"chairs"});
  const ChairPaint paint = wheelchair_colours(rng, ChairColours::kUniform);
  EXPECT_EQ(paint[0], Eigen::Vector3f(0x1.6533c8p-1f, 0x1.9e6406p-3f, 0x1.8838bep-2f));
  EXPECT_EQ(paint[1], Eigen::Vector3f(0x1.b6d146p-3f, 0x1.015d6cp-2f, 0x1.706c66p-2f));
  EXPECT_EQ(paint[2], Eigen::Vector3f::Constant(0x1.485c44p-5f));
  EXPECT_EQ(paint[3], Eigen::Vector3f(0x1.3474fp-1f, 0x1.1a6aa2p-1f, 0x1.8d1826p-2f));
}

TEST(WheelchairPalette, TheSeedDecides) {
  RandomStream a(8, {"chairs"}), b(8, {"chairs"}), c(9, {"chairs"});
  const ChairPaint x = wheelchair_colours(a, ChairColours::kPalette);
  EXPECT_EQ(x, wheelchair_colours(b, ChairColours::kPalette));
  EXPECT_NE(x, wheelchair_colours(c, ChairColours::kPalette));
}

}  // namespace
}  // namespace wheelpose::generate
