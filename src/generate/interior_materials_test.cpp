#include "generate/interior_materials.h"

#include <gtest/gtest.h>

namespace wheelpose::generate {
namespace {

// Colourfulness relative to brightness: 0 for grey, 1 for a pure primary.
float relative_chroma(const Eigen::Vector3f& c) {
  return (c.maxCoeff() - c.minCoeff()) / c.maxCoeff();
}

// Walls are light and quiet: bright, nearly grey, the two pattern colours close together.
TEST(InteriorMaterials, WallsAreLightQuietPaint) {
  RandomStream rng(3, {"walls"});
  for (int i = 0; i < 500; ++i) {
    const scene::Material m = interior_wall(rng, "walls");
    EXPECT_GT(m.texture.color_a.mean(), 0.25f) << i;
    EXPECT_LT(relative_chroma(m.texture.color_a), 0.35f) << i;  // cream is the most coloured
    EXPECT_LT((m.texture.color_a - m.texture.color_b).maxCoeff(), 0.07f) << i;
    EXPECT_LE(m.specular, 0.1f);
  }
}

TEST(InteriorMaterials, FloorsAreWoodTilesOrCarpetInTheirShares) {
  RandomStream rng(4, {"floors"});
  int wood = 0, tiles = 0, carpet = 0;
  const int n = 2000;
  for (int i = 0; i < n; ++i) {
    const scene::TextureKind kind = interior_floor(rng, "floor").texture.kind;
    wood += kind == scene::TextureKind::kWood;
    tiles += kind == scene::TextureKind::kChecker;
    carpet += kind == scene::TextureKind::kFabric;
  }
  EXPECT_EQ(wood + tiles + carpet, n);
  EXPECT_NEAR(wood / static_cast<double>(n), 0.5, 0.04);
  EXPECT_NEAR(tiles / static_cast<double>(n), 0.25, 0.04);
}

TEST(InteriorMaterials, TheSeedDecides) {
  RandomStream a(8, {"x"}), b(8, {"x"});
  for (int i = 0; i < 50; ++i) {
    const scene::Material x = interior_furniture(a, "o"), y = interior_furniture(b, "o");
    EXPECT_EQ(x.texture.kind, y.texture.kind);
    EXPECT_EQ(x.texture.color_a, y.texture.color_a);
    EXPECT_EQ(x.texture.seed, y.texture.seed);
  }
}

}  // namespace
}  // namespace wheelpose::generate
