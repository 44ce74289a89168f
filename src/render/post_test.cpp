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

// Automatic exposure brings the log-average luminance to the key: a dim grey room and a bright
// one come out the same, and an image of two halves lands at their geometric mean.
TEST(Post, AutoExposureMapsTheLogAverageToTheKey) {
  scene::PostProcess p;
  p.auto_exposure_key = 0.18f;
  // The log average is taken of luminance + 1e-4, so that black pixels count as very dark.
  for (float level : {0.01f, 0.5f, 4.0f}) {
    const cv::Mat img = flat(level, level, level);
    EXPECT_NEAR(at(apply_post_linear(img, no_depth(img), p, 5), 3, 3)[1],
                0.18f * level / (level + 1e-4f), 1e-5f)
        << level;
  }
  cv::Mat halves = flat(0.02f, 0.02f, 0.02f);
  halves(cv::Rect(0, 0, 20, 30)).setTo(cv::Scalar::all(0.32));
  const double log_average = std::sqrt((0.32 + 1e-4) * (0.02 + 1e-4));  // about 0.08
  const cv::Mat out = apply_post_linear(halves, no_depth(halves), p, 5);
  EXPECT_NEAR(at(out, 30, 3)[0], 0.02 * 0.18 / log_average, 1e-5);
  // The compensation still applies on top.
  p.exposure_ev = 1;
  const cv::Mat grey = flat(0.5f, 0.5f, 0.5f);
  EXPECT_NEAR(at(apply_post_linear(grey, no_depth(grey), p, 5), 3, 3)[0], 0.36f, 0.002f);
}

// Sensor noise: zero mean, variance g·shot·x + (g·read)², so a dark scene lifted by the exposure
// is noisier than a bright one at the same output level; seeded, so the same seed repeats.
TEST(Post, SensorNoiseGrowsInTheDarkAndFollowsTheSeed) {
  scene::PostProcess p;
  p.auto_exposure_key = 0.18f;
  p.shot_noise = 0.01f;
  p.read_noise = 0.002f;
  const auto noise_of = [&](float level, std::uint64_t seed) {
    const cv::Mat img = flat(level, level, level, 200, 200);
    cv::Mat out = apply_post_linear(img, no_depth(img), p, 5, seed);
    cv::Scalar mean, stddev;
    cv::meanStdDev(out.reshape(1), mean, stddev);
    return std::pair{mean[0], stddev[0]};
  };
  const auto [bright_mean, bright_sd] = noise_of(1.8f, 1);  // gain 0.1
  const auto [dark_mean, dark_sd] = noise_of(0.018f, 1);    // gain 10
  EXPECT_NEAR(bright_mean, 0.18, 0.002);
  EXPECT_NEAR(dark_mean, 0.18, 0.002);
  // Expected standard deviations: sqrt(g·0.01·0.18 + (g·0.002)²).
  EXPECT_NEAR(bright_sd, std::sqrt(0.1 * 0.01 * 0.18 + 0.0002 * 0.0002), 0.001);
  EXPECT_NEAR(dark_sd, std::sqrt(10 * 0.01 * 0.18 + 0.02 * 0.02), 0.005);
  const cv::Mat img = flat(0.2f, 0.2f, 0.2f);
  const cv::Mat a = apply_post_linear(img, no_depth(img), p, 5, 7);
  EXPECT_EQ(cv::norm(a, apply_post_linear(img, no_depth(img), p, 5, 7), cv::NORM_INF), 0.0);
  EXPECT_GT(cv::norm(a, apply_post_linear(img, no_depth(img), p, 5, 8), cv::NORM_INF), 0.0);
}

// The filmic curve: black stays black, it rises monotonically, mid grey is lifted, and
// highlights roll off below 1 instead of clipping until far above it.
TEST(Post, FilmicCurveRollsOffHighlights) {
  scene::PostProcess p;
  p.filmic = true;
  const auto through = [&](float v) {
    const cv::Mat img = flat(v, v, v);
    return at(apply_post_linear(img, no_depth(img), p, 5), 3, 3)[0];
  };
  EXPECT_NEAR(through(0), 0.0f, 1e-6f);
  EXPECT_NEAR(through(0.18f),
              0.18f * (2.51f * 0.18f + 0.03f) / (0.18f * (2.43f * 0.18f + 0.59f) + 0.14f), 1e-6f);
  float last = 0;
  for (float v = 0.05f; v < 10; v *= 1.5f) {
    const float out = through(v);
    EXPECT_GT(out, last) << v;
    last = out;
  }
  EXPECT_LT(through(1.0f), 0.85f);  // clipping would give 1
  EXPECT_EQ(through(50.0f), 1.0f);  // the fit reaches 1 near 14.6
}

}  // namespace
}  // namespace wheelpose::render
