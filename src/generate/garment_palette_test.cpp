#include "generate/garment_palette.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <opencv2/core.hpp>

#include "generate/furniture.h"
#include "render/texture.h"

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
                m.texture.kind == scene::TextureKind::kChecker ||
                m.texture.kind == scene::TextureKind::kImageDetail);
    EXPECT_LE(m.texture.color_a.maxCoeff(), 0.95f);
  }
  EXPECT_NEAR(saturated_count / static_cast<double>(n), 0.2, 0.03);
}

TEST(GarmentPalette, PlainWeavesAreMostAndTheSeedDecides) {
  RandomStream a(9, {"garments"}), b(9, {"garments"});
  int plain = 0, photo = 0;
  for (int i = 0; i < 1000; ++i) {
    const scene::Material x = garment_material(a, "bottom", GarmentColours::kPalette);
    const scene::Material y = garment_material(b, "bottom", GarmentColours::kPalette);
    EXPECT_EQ(x.texture.color_a, y.texture.color_a);
    EXPECT_EQ(x.texture.seed, y.texture.seed);
    EXPECT_EQ(x.texture.path, y.texture.path);
    plain += x.texture.kind == scene::TextureKind::kFabric;
    if (x.texture.kind == scene::TextureKind::kImageDetail) {
      ++photo;
      // The photo's detail carries the garment's colour; the photo is one of the list.
      EXPECT_EQ(x.diffuse, x.texture.color_a);
      EXPECT_NE(std::find(fabric_photos().begin(), fabric_photos().end(), x.texture.path),
                fabric_photos().end());
    }
  }
  EXPECT_NEAR((plain + photo) / 1000.0, 0.6, 0.05);
  EXPECT_NEAR(photo / 1000.0, kPhotoFabricShare, 0.05);
}

// Every fabric photo is in the installed package and keeps a weave: its detail averages 1 and
// varies (a flat photo would add nothing).
TEST(GarmentPalette, FabricPhotosLoadAsDetailAveragingOne) {
  if (!std::filesystem::exists(FurnitureCatalog::default_archive())) {
    GTEST_SKIP() << "sweethome3d-furniture missing: run scripts/setup.sh";
  }
  for (const std::string& path : fabric_photos()) {
    const cv::Mat detail = render::load_detail_image(path, "fabric");
    EXPECT_LE(std::max(detail.cols, detail.rows), render::kDetailSize) << path;
    cv::Scalar mean, deviation;
    cv::meanStdDev(detail, mean, deviation);
    EXPECT_NEAR(mean[0], 1.0, 1e-3) << path;
    EXPECT_GT(deviation[0], 0.03) << path;
  }
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
