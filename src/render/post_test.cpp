#include "render/post.h"

#include <gtest/gtest.h>

#include <cmath>

#include "render/texture.h"

namespace wheelpose::render {
namespace {

cv::Mat flat(float r, float g, float b, int w = 40, int h = 30) {
  return cv::Mat(h, w, CV_32FC3, cv::Scalar(r, g, b));
}
cv::Mat no_depth(const cv::Mat& img) { return cv::Mat(img.size(), CV_32F, cv::Scalar(0)); }

cv::Vec3f at(const cv::Mat& m, int x, int y) { return m.at<cv::Vec3f>(y, x); }

TEST(Post, NeutralSettingsChangeNothing) {
  const cv::Mat img = flat(0.3f, 0.5f, 0.7f);
  const cv::Mat out = apply_post_linear(img, no_depth(img), {}, 5.0f);
  EXPECT_LT(cv::norm(out, img, cv::NORM_INF), 1e-6);
}

TEST(Post, ExposureOneStopDoubles) {
  const cv::Mat img = flat(0.1f, 0.2f, 0.3f);
  scene::PostProcess p;
  p.exposure_ev = 1;
  const cv::Vec3f c = at(apply_post_linear(img, no_depth(img), p, 5), 3, 3);
  EXPECT_NEAR(c[0], 0.2f, 1e-6f);
  EXPECT_NEAR(c[2], 0.6f, 1e-6f);
}

TEST(Post, WarmTemperatureRaisesRedAndLowersBlue) {
  const cv::Mat img = flat(0.5f, 0.5f, 0.5f);
  scene::PostProcess p;
  p.temperature = 50;
  const cv::Vec3f c = at(apply_post_linear(img, no_depth(img), p, 5), 3, 3);
  EXPECT_GT(c[0], 0.5f);
  EXPECT_LT(c[2], 0.5f);
  EXPECT_NEAR(0.2126f * c[0] + 0.7152f * c[1] + 0.0722f * c[2], 0.5f, 1e-5f);
  p.temperature = -50;
  const cv::Vec3f cold = at(apply_post_linear(img, no_depth(img), p, 5), 3, 3);
  EXPECT_LT(cold[0], cold[2]);
}

TEST(Post, ContrastSpreadsValuesAroundMidGrey) {
  cv::Mat img = flat(0.05f, 0.18f, 0.6f);
  scene::PostProcess p;
  p.contrast = 50;
  const cv::Vec3f c = at(apply_post_linear(img, no_depth(img), p, 5), 1, 1);
  EXPECT_LT(c[0], 0.05f);
  EXPECT_NEAR(c[1], 0.18f, 1e-6f);
  EXPECT_GT(c[2], 0.6f);
  p.contrast = -100;  // no contrast at all: everything mid grey
  const cv::Vec3f g = at(apply_post_linear(img, no_depth(img), p, 5), 1, 1);
  EXPECT_NEAR(g[0], 0.18f, 1e-6f);
  EXPECT_NEAR(g[2], 0.18f, 1e-6f);
}

TEST(Post, SaturationZeroGivesGreyAndPositiveMoreColour) {
  const cv::Mat img = flat(0.6f, 0.3f, 0.1f);
  scene::PostProcess p;
  p.saturation = -100;
  const cv::Vec3f g = at(apply_post_linear(img, no_depth(img), p, 5), 0, 0);
  EXPECT_NEAR(g[0], g[1], 1e-6f);
  EXPECT_NEAR(g[1], g[2], 1e-6f);
  p.saturation = 50;
  const cv::Vec3f s = at(apply_post_linear(img, no_depth(img), p, 5), 0, 0);
  EXPECT_GT(s[0] - s[2], 0.6f - 0.1f);
}

TEST(Post, VignetteDarkensCornersNotTheCentre) {
  const cv::Mat img = flat(0.5f, 0.5f, 0.5f);
  scene::PostProcess p;
  p.vignette = 0.5f;
  const cv::Mat out = apply_post_linear(img, no_depth(img), p, 5);
  EXPECT_NEAR(at(out, 20, 15)[0], 0.5f, 1e-6f);
  EXPECT_LT(at(out, 0, 0)[0], 0.3f);
  EXPECT_LT(at(out, 39, 29)[0], 0.3f);
  EXPECT_GT(at(out, 0, 0)[0], 0.24f);  // at most 1 − vignette
}

TEST(Post, BloomSpreadsLightAroundBrightPixels) {
  cv::Mat img = flat(0.1f, 0.1f, 0.1f, 64, 64);
  img(cv::Rect(30, 30, 4, 4)).setTo(cv::Scalar(8, 8, 8));
  scene::PostProcess p;
  p.bloom = 0.5f;
  const cv::Mat out = apply_post_linear(img, no_depth(img), p, 5);
  EXPECT_GT(at(out, 37, 32)[0], 0.12f);        // near the bright spot
  EXPECT_NEAR(at(out, 2, 2)[0], 0.1f, 0.01f);  // far away: unchanged
}

TEST(Post, FilmGrainAddsSeededNoiseKeepingTheMean) {
  const cv::Mat img = flat(0.2f, 0.2f, 0.2f, 64, 64);
  scene::PostProcess p;
  p.film_grain = 0.5f;
  const cv::Mat a = apply_post(img, no_depth(img), p, 5, 1);
  const cv::Mat clean = apply_post(img, no_depth(img), {}, 5, 1);
  cv::Scalar mean, stddev, clean_mean, clean_stddev;
  cv::meanStdDev(a, mean, stddev);
  cv::meanStdDev(clean, clean_mean, clean_stddev);
  EXPECT_EQ(clean_stddev[0], 0.0);
  EXPECT_GT(stddev[0], 3.0);
  EXPECT_NEAR(mean[0], clean_mean[0], 1.5);
  EXPECT_EQ(cv::norm(a, apply_post(img, no_depth(img), p, 5, 1), cv::NORM_INF), 0.0);
  EXPECT_GT(cv::norm(a, apply_post(img, no_depth(img), p, 5, 2), cv::NORM_INF), 0.0);
}

TEST(Post, LensBlurKeepsTheFocalPlaneSharpAndBlursTheRest) {
  // Vertical stripes; the left half is at the focus distance, the right half far behind it.
  cv::Mat img(32, 64, CV_32FC3);
  cv::Mat depth(32, 64, CV_32F);
  for (int y = 0; y < 32; ++y) {
    for (int x = 0; x < 64; ++x) {
      const float v = (x / 2) % 2 ? 1.0f : 0.0f;
      img.at<cv::Vec3f>(y, x) = cv::Vec3f(v, v, v);
      depth.at<float>(y, x) = x < 32 ? 4.0f : 40.0f;
    }
  }
  scene::PostProcess p;
  p.lens_blur = 6;
  const cv::Mat out = apply_post_linear(img, depth, p, 4.0f);
  for (int x = 4; x < 28; ++x) EXPECT_EQ(at(out, x, 16)[0], at(img, x, 16)[0]) << x;
  for (int x = 40; x < 60; ++x) {
    EXPECT_GT(at(out, x, 16)[0], 0.2f) << x;
    EXPECT_LT(at(out, x, 16)[0], 0.8f) << x;
  }
}

TEST(Post, SrgbEncodingMatchesTheStandard) {
  const cv::Mat img = flat(0.0f, 0.5f, 1.0f, 2, 2);
  const cv::Vec3b c = encode_srgb(img).at<cv::Vec3b>(0, 0);
  EXPECT_EQ(c, cv::Vec3b(0, 188, 255));
  EXPECT_EQ(encode_srgb(flat(-1.0f, 0.0031308f, 7.0f, 1, 1)).at<cv::Vec3b>(0, 0),
            cv::Vec3b(0, 10, 255));
}

}  // namespace
}  // namespace wheelpose::render
