#include "render/post.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "core/random.h"
#include "render/motion_blur.h"
#include "render/texture.h"

namespace wheelpose::render {
namespace {

constexpr float kMidGrey = 0.18f;

float luminance(const cv::Vec3f& c) { return 0.2126f * c[0] + 0.7152f * c[1] + 0.0722f * c[2]; }

cv::Mat blur(const cv::Mat& image, double sigma) {
  cv::Mat out;
  cv::GaussianBlur(image, out, cv::Size(0, 0), sigma, sigma, cv::BORDER_REFLECT);
  return out;
}

// Depth-of-field blur: a circle of confusion per pixel from its depth, blending between the sharp
// image and three blur levels (cheap and smooth, unlike a true per-pixel gather).
cv::Mat lens_blur(const cv::Mat& linear, const cv::Mat& depth, float max_radius, float focus) {
  const std::array<float, 3> radii = {max_radius / 4, max_radius / 2, max_radius};
  std::array<cv::Mat, 4> levels = {linear, blur(linear, std::max(0.3f, radii[0] / 2)),
                                   blur(linear, std::max(0.3f, radii[1] / 2)),
                                   blur(linear, std::max(0.3f, radii[2] / 2))};
  cv::Mat out(linear.size(), linear.type());
  // Each pixel is a pure function of its own inputs: rows in parallel give the same image.
  cv::parallel_for_(cv::Range(0, linear.rows), [&](const cv::Range& rows) {
    for (int y = rows.start; y < rows.end; ++y) {
      const float* d_row = depth.ptr<float>(y);
      std::array<const cv::Vec3f*, 4> level_row;
      for (int i = 0; i < 4; ++i) level_row[i] = levels[i].ptr<cv::Vec3f>(y);
      cv::Vec3f* o = out.ptr<cv::Vec3f>(y);
      for (int x = 0; x < linear.cols; ++x) {
        const float d = d_row[x];
        const float coc =
            d > 0 ? std::min(max_radius, max_radius * std::abs(d - focus) / std::max(d, 1e-3f))
                  : max_radius;
        // Position of coc on the level scale 0, r/4, r/2, r.
        float lo_r = 0;
        int level = 0;
        for (; level < 3 && coc > radii[level]; ++level) lo_r = radii[level];
        if (level == 3) {
          o[x] = level_row[3][x];
          continue;
        }
        const float t = (coc - lo_r) / std::max(1e-6f, radii[level] - lo_r);
        o[x] = level_row[level][x] * (1 - t) + level_row[level + 1][x] * t;
      }
    }
  });
  return out;
}

// The gain that brings the image's log-average luminance to `key` (Reinhard's scene key). A
// serial sum in row order, so the gain does not depend on threads.
float auto_exposure_gain(const cv::Mat& linear, float key) {
  double log_sum = 0;
  for (int y = 0; y < linear.rows; ++y) {
    const cv::Vec3f* row = linear.ptr<cv::Vec3f>(y);
    for (int x = 0; x < linear.cols; ++x)
      log_sum += std::log(1e-4 + std::max(0.0f, luminance(row[x])));
  }
  const double log_average = std::exp(log_sum / std::max(1, linear.rows * linear.cols));
  return static_cast<float>(key / log_average);
}

// Poisson–Gaussian sensor noise on an image already multiplied by `gain` (see PostProcess).
// One stream per row, so the result is the same for any thread count.
void add_sensor_noise(cv::Mat& img, const scene::PostProcess& p, float gain, std::uint64_t seed) {
  cv::parallel_for_(cv::Range(0, img.rows), [&](const cv::Range& rows) {
    for (int y = rows.start; y < rows.end; ++y) {
      RandomStream rng(seed, {"sensor", y});
      cv::Vec3f* row = img.ptr<cv::Vec3f>(y);
      for (int x = 0; x < img.cols; ++x) {
        for (int i = 0; i < 3; ++i) {
          const float v = std::max(0.0f, row[x][i]);
          const float variance =
              gain * p.shot_noise * v + gain * gain * p.read_noise * p.read_noise;
          row[x][i] = v + std::sqrt(variance) * static_cast<float>(rng.normal(0.0, 1.0));
        }
      }
    }
  });
}

// The ACES filmic fit (Narkowicz 2015): a toe, a roughly linear middle and a shoulder that rolls
// highlights off to 1 instead of clipping them.
float filmic(float x) {
  x = std::max(0.0f, x);
  return std::min(1.0f, x * (2.51f * x + 0.03f) / (x * (2.43f * x + 0.59f) + 0.14f));
}

}  // namespace

cv::Mat apply_post_linear(const cv::Mat& linear, const cv::Mat& depth, const scene::PostProcess& p,
                          float focus_distance, std::uint64_t seed, const cv::Mat& motion) {
  CV_Assert(linear.type() == CV_32FC3);
  // The camera meters the scene before it takes the picture: blur moves light about but does
  // not change the exposure, so pixels far from a streak keep their values.
  const float metered =
      p.auto_exposure_key > 0 ? auto_exposure_gain(linear, p.auto_exposure_key) : 1.0f;
  cv::Mat img = motion_blur(linear, depth, motion);
  if (p.lens_blur > 0) img = lens_blur(img, depth, p.lens_blur, focus_distance);
  // Exposure and white balance are one gain per channel. Temperature tilts red against blue,
  // normalised so the luminance of grey stays put.
  const float k = 0.3f * p.temperature / 100.0f;
  cv::Vec3f gain(1 + k, 1, 1 - k);
  gain /= luminance(gain);
  const float exposure = metered * std::exp2(p.exposure_ev);
  gain *= exposure;
  img.forEach<cv::Vec3f>([&](cv::Vec3f& c, const int*) { c = c.mul(gain); });
  if (p.shot_noise > 0 || p.read_noise > 0) add_sensor_noise(img, p, exposure, seed);
  if (p.bloom > 0) {
    // Glow from what exceeds the threshold, blurred at quarter resolution for speed.
    cv::Mat bright;
    cv::max(img - cv::Scalar::all(p.bloom_threshold), cv::Scalar::all(0), bright);
    cv::Mat small, glow;
    cv::resize(bright, small, cv::Size(std::max(1, img.cols / 4), std::max(1, img.rows / 4)), 0, 0,
               cv::INTER_AREA);
    const double sigma = std::max(1.0, 0.01 * std::hypot(small.cols, small.rows));
    cv::resize(blur(small, sigma), glow, img.size(), 0, 0, cv::INTER_LINEAR);
    img += glow * (4.0 * p.bloom);
  }
  const float contrast = 1.0f + p.contrast / 100.0f;
  if (contrast != 1.0f) {
    // Power curve about mid grey: steeper above and below it for contrast > 0. OpenCV's
    // vectorised pow over the whole image (negative values clamp to 0 first).
    cv::Mat channels = img.reshape(1);
    cv::max(channels, 0.0, channels);
    channels *= 1.0 / kMidGrey;
    cv::pow(channels, contrast, channels);
    channels *= kMidGrey;
  }
  const float saturation = 1.0f + p.saturation / 100.0f;
  const float cx = 0.5f * img.cols, cy = 0.5f * img.rows;
  const float corner = std::hypot(cx, cy);
  img.forEach<cv::Vec3f>([&](cv::Vec3f& c, const int* pos) {
    if (saturation != 1.0f) {
      const float l = luminance(c);
      for (int i = 0; i < 3; ++i) c[i] = std::max(0.0f, l + (c[i] - l) * saturation);
    }
    if (p.vignette > 0) {
      // 1 in the middle, falling smoothly to 1 − vignette in the corners.
      const float r = std::hypot(pos[1] + 0.5f - cx, pos[0] + 0.5f - cy) / corner;
      const float t = std::clamp((r - 0.3f) / 0.7f, 0.0f, 1.0f);
      c *= 1.0f - p.vignette * t * t * (3 - 2 * t);
    }
    if (p.filmic) {
      for (int i = 0; i < 3; ++i) c[i] = filmic(c[i]);
    }
  });
  return img;
}

cv::Mat encode_srgb(const cv::Mat& linear) {
  cv::Mat out(linear.size(), CV_8UC3);
  // A table over 4096 steps of [0, 1] keeps encoding cheap for 1280×720 frames.
  static const std::array<std::uint8_t, 4097> table = [] {
    std::array<std::uint8_t, 4097> t{};
    for (int i = 0; i <= 4096; ++i) {
      t[i] = static_cast<std::uint8_t>(std::lround(255.0f * linear_to_srgb(i / 4096.0f)));
    }
    return t;
  }();
  cv::parallel_for_(cv::Range(0, linear.rows), [&](const cv::Range& rows) {
    for (int y = rows.start; y < rows.end; ++y) {
      const cv::Vec3f* in = linear.ptr<cv::Vec3f>(y);
      cv::Vec3b* o = out.ptr<cv::Vec3b>(y);
      for (int x = 0; x < linear.cols; ++x) {
        for (int i = 0; i < 3; ++i) {
          const float c = std::clamp(in[x][i], 0.0f, 1.0f);
          o[x][i] = table[static_cast<int>(c * 4096.0f + 0.5f)];
        }
      }
    }
  });
  return out;
}

cv::Mat apply_post(const cv::Mat& linear, const cv::Mat& depth, const scene::PostProcess& p,
                   float focus_distance, std::uint64_t seed, const cv::Mat& motion) {
  cv::Mat out = encode_srgb(apply_post_linear(linear, depth, p, focus_distance, seed, motion));
  if (p.film_grain > 0) {
    // Grain in display space, strongest in the mid-tones. One stream per row (a row is never
    // split between threads), so the result is the same for any thread count.
    const float amount = 24.0f * p.film_grain;
    cv::parallel_for_(cv::Range(0, out.rows), [&](const cv::Range& rows) {
      for (int y = rows.start; y < rows.end; ++y) {
        RandomStream rng(seed, {"grain", y});
        cv::Vec3b* row = out.ptr<cv::Vec3b>(y);
        for (int x = 0; x < out.cols; ++x) {
          cv::Vec3b& c = row[x];
          const float n = static_cast<float>(rng.normal(0.0, 1.0));
          const float l = (c[0] + c[1] + c[2]) / (3.0f * 255.0f);
          const float g = amount * n * (0.4f + 2.4f * l * (1 - l));
          for (int i = 0; i < 3; ++i) c[i] = cv::saturate_cast<std::uint8_t>(c[i] + g);
        }
      }
    });
  }
  return out;
}

}  // namespace wheelpose::render
