#include "generate/garment_palette.h"

#include <gtest/gtest.h>

namespace wheelpose::generate {
namespace {

// The palette shade nearest to `c` after undoing the brightness jitter (relative distance).
double distance_to_palette(const Eigen::Vector3f& c, bool* saturated) {
  double best = INFINITY;
  for (const GarmentShade& s : garment_palette()) {
    const Eigen::Vector3f shade(s.r, s.g, s.b);
    for (float k = 0.83f; k <= 1.17f; k += 0.01f) {
      const double d =
          ((c - shade * k).cwiseAbs().array() / (shade * k).array().max(0.01f)).maxCoeff();
      if (d < best) {
        best = d;
        *saturated = s.saturated;
      }
    }
  }
  return best;
}

TEST(GarmentPalette, ColoursComeFromThePaletteFourFifthsMuted) {
  RandomStream rng(5, {"garments"});
  int saturated_count = 0;
  const int n = 2000;
  for (int i = 0; i < n; ++i) {
    const scene::Material m = garment_material(rng, "top", GarmentColours::kPalette);
    bool saturated = false;
    EXPECT_LT(distance_to_palette(m.texture.color_a, &saturated), 0.06) << i;
    saturated_count += saturated;
    EXPECT_TRUE(m.texture.kind == scene::TextureKind::kFabric ||
                m.texture.kind == scene::TextureKind::kNoise ||
                m.texture.kind == scene::TextureKind::kStripes ||
                m.texture.kind == scene::TextureKind::kChecker);
    EXPECT_LE(m.texture.color_a.maxCoeff(), 0.95f);
  }
  EXPECT_NEAR(saturated_count / static_cast<double>(n), 0.2, 0.03);
}

TEST(GarmentPalette, PlainWeavesAreMostAndTheSeedDecides) {
  RandomStream a(9, {"garments"}), b(9, {"garments"});
  int plain = 0;
  for (int i = 0; i < 1000; ++i) {
    const scene::Material x = garment_material(a, "bottom", GarmentColours::kPalette);
    const scene::Material y = garment_material(b, "bottom", GarmentColours::kPalette);
    EXPECT_EQ(x.texture.color_a, y.texture.color_a);
    EXPECT_EQ(x.texture.seed, y.texture.seed);
    plain += x.texture.kind == scene::TextureKind::kFabric;
  }
  EXPECT_NEAR(plain / 1000.0, 0.6, 0.05);
}

// The black swatch (sRGB 0x1c1c1e) in linear light: 28/255 decoded by the sRGB curve.
TEST(GarmentPalette, SwatchesAreDecodedFromSrgb) {
  const GarmentShade& black = garment_palette().front();
  EXPECT_STREQ(black.name, "black");
  EXPECT_NEAR(black.r, 0.011612, 1e-5);
  EXPECT_NEAR(black.b, 0.012983, 1e-5);
}

}  // namespace
}  // namespace wheelpose::generate
