#include "render/texture.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "core/error.h"

namespace wheelpose::render {
namespace {

TEST(Texture, SrgbRoundTrips) {
  for (float c : {0.0f, 0.002f, 0.04f, 0.2f, 0.5f, 0.9f, 1.0f}) {
    EXPECT_NEAR(srgb_to_linear(linear_to_srgb(c)), c, 1e-5f);
  }
  EXPECT_NEAR(srgb_to_linear(0.5f), 0.21404f, 1e-5f);
}

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

TEST(Texture, NoiseDependsOnTheSeedOnly) {
  scene::Texture a, b;
  a.kind = b.kind = scene::TextureKind::kNoise;
  b.seed = 5;
  EXPECT_EQ(procedural_pattern(a, 1.3f, 2.7f), procedural_pattern(a, 1.3f, 2.7f));
  EXPECT_NE(procedural_pattern(a, 1.3f, 2.7f), procedural_pattern(b, 1.3f, 2.7f));
}

TEST(Texture, ImagesAreDecodedToLinearAndBadFilesAreErrors) {
  const auto dir = std::filesystem::temp_directory_path() / "wheelpose_texture_test";
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

}  // namespace
}  // namespace wheelpose::render
