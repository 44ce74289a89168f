#include "render/texture.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "core/error.h"

namespace wheelpose::render {
namespace {

TEST(Texture, HueRotationOf120DegreesTurnsRedIntoGreen) {
  const Eigen::Vector3f g = rotate_hue({1, 0, 0}, 120);
  EXPECT_NEAR(g.x(), 0.0f, 1e-5f);
  EXPECT_NEAR(g.y(), 1.0f, 1e-5f);
  EXPECT_NEAR(g.z(), 0.0f, 1e-5f);
  const Eigen::Vector3f grey = rotate_hue({0.3f, 0.3f, 0.3f}, 77);
  EXPECT_NEAR(grey.x(), 0.3f, 1e-5f);
  EXPECT_NEAR(grey.z(), 0.3f, 1e-5f);
  EXPECT_NEAR(rotate_hue({0.2f, 0.5f, 0.4f}, 33).sum(), 1.1f, 1e-5f);
}

TEST(Texture, ProceduralPatternsStayInRangeAndVary) {
  for (auto kind :
       {scene::TextureKind::kNoise, scene::TextureKind::kStripes, scene::TextureKind::kChecker,
        scene::TextureKind::kFabric, scene::TextureKind::kWood, scene::TextureKind::kMarble}) {
    scene::Texture t;
    t.kind = kind;
    float lo = 1, hi = 0;
    for (int i = 0; i < 400; ++i) {
      const float v = procedural_pattern(t, 0.037f * i, 0.051f * (i % 37));
      ASSERT_GE(v, 0.0f);
      ASSERT_LE(v, 1.0f);
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
    EXPECT_GT(hi - lo, 0.3f) << static_cast<int>(kind);
  }
  scene::Texture checker;
  checker.kind = scene::TextureKind::kChecker;
  EXPECT_EQ(procedural_pattern(checker, 0.5f, 0.5f), 0.0f);
  EXPECT_EQ(procedural_pattern(checker, 1.5f, 0.5f), 1.0f);
  EXPECT_EQ(procedural_pattern(checker, -0.5f, 0.5f), 1.0f);
}

// Detail finer than the pixel fades to the pattern's mean: the spread of values shrinks as the
// footprint grows, reaching a constant once every octave (or thread) is below a pixel.
TEST(Texture, DetailFinerThanThePixelFadesToItsMean) {
  for (auto kind : {scene::TextureKind::kNoise, scene::TextureKind::kFabric,
                    scene::TextureKind::kWood, scene::TextureKind::kMarble}) {
    scene::Texture t;
    t.kind = kind;
    auto spread = [&](float footprint) {
      float lo = 1, hi = 0;
      for (int i = 0; i < 400; ++i) {
        const float u = 0.037f * i, v = 0.051f * (i % 37);
        // A point footprint is the unfiltered pattern.
        if (footprint == 0) {
          EXPECT_EQ(procedural_pattern(t, u, v, 0), procedural_pattern(t, u, v));
        }
        const float x = procedural_pattern(t, u, v, footprint);
        lo = std::min(lo, x);
        hi = std::max(hi, x);
      }
      return hi - lo;
    };
    const float sharp = spread(0), soft = spread(0.2f), gone = spread(100);
    if (kind == scene::TextureKind::kNoise || kind == scene::TextureKind::kFabric) {
      EXPECT_LT(soft, sharp) << static_cast<int>(kind);
      EXPECT_EQ(gone, 0.0f) << static_cast<int>(kind);  // nothing left but the mean
    }
  }
  // Rings and veins are coarser than any octave: they stay, and only their noise warp fades to
  // its mean (fbm = 0.5).
  scene::Texture wood, marble;
  wood.kind = scene::TextureKind::kWood;
  marble.kind = scene::TextureKind::kMarble;
  const float u = 0.7f, v = 0.3f, pi = 3.14159265f;
  const float r = std::sqrt((u + 0.3f) * (u + 0.3f) + 0.1f * v * v);
  const float ring = r + 0.3f * wood.turbulence * 0.5f;
  EXPECT_NEAR(procedural_pattern(wood, u, v, 100), std::pow(ring - std::floor(ring), 3.0f), 1e-5f);
  EXPECT_NEAR(procedural_pattern(marble, u, v, 100),
              0.5f + 0.5f * std::sin(pi * (u + v) + 4.0f * marble.turbulence * 0.5f), 1e-5f);
  scene::Texture noise;
  noise.kind = scene::TextureKind::kNoise;
  EXPECT_FLOAT_EQ(procedural_pattern(noise, 3.1f, 4.2f, 100), 0.5f);
}

TEST(Texture, NoiseDependsOnTheSeedOnly) {
  scene::Texture a, b;
  a.kind = b.kind = scene::TextureKind::kNoise;
  b.seed = 5;
  EXPECT_EQ(procedural_pattern(a, 1.3f, 2.7f), procedural_pattern(a, 1.3f, 2.7f));
  EXPECT_NE(procedural_pattern(a, 1.3f, 2.7f), procedural_pattern(b, 1.3f, 2.7f));
}

TEST(Texture, ImagesAreDecodedToLinearAndBadFilesAreErrors) {
  // Per process: the per-ISA copies of this test binary run at the same time under ctest -j.
  const auto dir = std::filesystem::temp_directory_path() /
                   ("wheelpose_texture_test_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  cv::Mat bgr(2, 2, CV_8UC3, cv::Scalar(0, 0, 255));  // red
  bgr.at<cv::Vec3b>(1, 1) = cv::Vec3b(128, 128, 128);
  ASSERT_TRUE(cv::imwrite((dir / "t.png").string(), bgr));
  const cv::Mat img = load_linear_image((dir / "t.png").string(), "/x");
  EXPECT_EQ(img.at<cv::Vec3f>(0, 0), cv::Vec3f(1, 0, 0));
  EXPECT_NEAR(img.at<cv::Vec3f>(1, 1)[0], srgb_to_linear(128 / 255.0f), 1e-6f);
  // Bilinear sampling at a texel centre returns it exactly.
  EXPECT_NEAR(sample_bilinear(img, 0.25f, 0.25f).x(), 1.0f, 1e-6f);

  std::ofstream(dir / "empty.png").close();
  try {
    load_linear_image((dir / "empty.png").string(), "/materials/3/texture/path");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("/materials/3/texture/path: cannot read image"),
              std::string::npos);
    EXPECT_NE(std::string(e.what()).find("empty.png"), std::string::npos);
  }
  EXPECT_THROW(load_linear_image((dir / "missing.png").string(), "/x"), Error);
  std::filesystem::remove_all(dir);
}

// An image detail texture: the photo's luminance over its mean (1 on average, the same in every
// channel), repeated `scale` times per uv unit, so the material colour sets the hue.
TEST(Texture, ImageDetailIsTheLuminanceOverItsMeanRepeated) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("wheelpose_detail_test_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  cv::Mat bgr(2, 2, CV_8UC3, cv::Scalar(255, 255, 255));  // white, one black texel
  bgr.at<cv::Vec3b>(0, 0) = cv::Vec3b(0, 0, 0);
  ASSERT_TRUE(cv::imwrite((dir / "weave.png").string(), bgr));
  scene::Texture t;
  t.kind = scene::TextureKind::kImageDetail;
  t.scale = 2;
  const TextureSampler sampler(t, (dir / "weave.png").string(), "/x");
  // Luminance 0 and three 1s: mean 0.75, so 0 and 4/3.
  EXPECT_NEAR(sampler.image().at<cv::Vec3f>(0, 0)[1], 0.0f, 1e-6f);
  EXPECT_NEAR(sampler.image().at<cv::Vec3f>(1, 1)[0], 4.0f / 3.0f, 1e-5f);
  // The black texel (top left of the image) sits at v just below 1 and again half a uv unit on.
  EXPECT_NEAR(sampler.at(0.125f, 0.875f).x(), 0.0f, 1e-5f);
  EXPECT_NEAR(sampler.at(0.625f, 0.375f).x(), 0.0f, 1e-5f);
  EXPECT_NEAR(sampler.at(0.375f, 0.875f).y(), 4.0f / 3.0f, 1e-5f);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace wheelpose::render
