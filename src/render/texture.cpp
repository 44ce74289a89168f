#include "render/texture.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <mutex>
#include <numbers>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/archive_member.h"
#include "core/error.h"
#include "core/image_read.h"
#include "core/random.h"

namespace wheelpose::render {
namespace {

constexpr float kTwoPi = 2.0f * std::numbers::pi_v<float>;

// Lattice value in [0, 1) from a seed and integer coordinates (a hash, so noise is a pure
// function of the texture's seed). One avalanche over a weighted sum of the coordinates: fbm
// evaluates 16 of these per texture lookup.
float lattice(std::uint64_t seed, int x, int y) {
  const std::uint64_t h =
      StreamKey::mix(seed + static_cast<std::uint32_t>(x) * 0x9e3779b97f4a7c15ULL +
                     static_cast<std::uint32_t>(y) * 0xc2b2ae3d27d4eb4fULL);
  return static_cast<float>(h >> 40) * (1.0f / 16777216.0f);
}

float smooth(float t) { return t * t * (3.0f - 2.0f * t); }

float value_noise(std::uint64_t seed, float u, float v) {
  const float fu = std::floor(u), fv = std::floor(v);
  const int x = static_cast<int>(fu), y = static_cast<int>(fv);
  const float tx = smooth(u - fu), ty = smooth(v - fv);
  const float a = lattice(seed, x, y), b = lattice(seed, x + 1, y);
  const float c = lattice(seed, x, y + 1), d = lattice(seed, x + 1, y + 1);
  return (a + (b - a) * tx) + ((c + (d - c) * tx) - (a + (b - a) * tx)) * ty;
}

// How much of a pattern of `frequency` cycles per unit survives a pixel `footprint` units wide:
// 1 while a cycle spans two or more pixels, fading to 0 (the pattern's mean) once it spans
// less than two thirds of one.
float detail_weight(float footprint, float frequency) {
  return std::clamp(1.5f - footprint * frequency, 0.0f, 1.0f);
}

// Fractal sum of four octaves, in [0, 1]. Octaves finer than the footprint fade to their mean
// (and are not evaluated once gone), so distant noise neither aliases nor costs its fine octaves.
float fbm(std::uint64_t seed, float u, float v, float footprint) {
  float sum = 0.0f, amp = 0.5f, norm = 0.0f, frequency = 1.0f;
  for (int o = 0; o < 4; ++o) {
    const float w = detail_weight(footprint, frequency);
    if (w >= 1.0f) {
      sum += amp * value_noise(seed + o, u, v);
    } else if (w > 0.0f) {
      sum += amp * (w * value_noise(seed + o, u, v) + (1.0f - w) * 0.5f);
    } else {
      sum += amp * 0.5f;
    }
    norm += amp;
    amp *= 0.5f;
    u *= 2.0f;
    v *= 2.0f;
    frequency *= 2.0f;
  }
  return sum / norm;
}

float fract(float x) { return x - std::floor(x); }

}  // namespace

cv::Mat load_linear_image(const std::string& path, const std::string& what) {
  // Checked first so OpenCV does not print its own warning for a missing file (an archive's
  // entry: read_image names what is missing).
  if (!archive_member(path) && !std::filesystem::is_regular_file(path))
    throw Error(what + ": image '" + path + "' not found");
  cv::Mat raw;
  try {
    raw = read_image(path, cv::IMREAD_ANYDEPTH | cv::IMREAD_COLOR);
  } catch (const Error& e) {
    throw Error(what + ": cannot read image: " + e.what());
  }
  cv::Mat rgb;
  cv::cvtColor(raw, rgb, cv::COLOR_BGR2RGB);
  cv::Mat out;
  if (rgb.depth() == CV_32F) return rgb;
  const double scale = rgb.depth() == CV_16U ? 1.0 / 65535.0 : 1.0 / 255.0;
  rgb.convertTo(out, CV_32FC3, scale);
  // A 256-entry table would only serve 8-bit inputs; textures are decoded once, so keep it simple.
  out.forEach<cv::Vec3f>([](cv::Vec3f& p, const int*) {
    for (int k = 0; k < 3; ++k) p[k] = srgb_to_linear(p[k]);
  });
  return out;
}

cv::Mat load_detail_image(const std::string& path, const std::string& what) {
  // Decoded once per process: every frame's garments draw from the same few photos.
  static std::mutex mutex;
  static std::map<std::string, cv::Mat> cache;
  {
    const std::lock_guard<std::mutex> lock(mutex);
    if (const auto it = cache.find(path); it != cache.end()) return it->second;
  }
  const cv::Mat rgb = load_linear_image(path, what);
  cv::Mat luminance;
  cv::transform(rgb, luminance, cv::Matx13f(0.2126f, 0.7152f, 0.0722f));
  const int longer = std::max(luminance.cols, luminance.rows);
  if (longer > kDetailSize) {
    const double f = static_cast<double>(kDetailSize) / longer;
    cv::resize(luminance, luminance, cv::Size(), f, f, cv::INTER_AREA);
  }
  const double mean = cv::mean(luminance)[0];
  if (!(mean > 0)) throw Error(what + ": image '" + path + "' is black: no detail to keep");
  luminance *= 1.0 / mean;
  cv::Mat detail;
  cv::merge(std::vector<cv::Mat>{luminance, luminance, luminance}, detail);
  const std::lock_guard<std::mutex> lock(mutex);
  return cache.emplace(path, detail).first->second;
}

Eigen::Vector3f sample_bilinear(const cv::Mat& image, float u, float v) {
  const int w = image.cols, h = image.rows;
  const float x = fract(u) * w - 0.5f, y = fract(v) * h - 0.5f;
  const float fx = std::floor(x), fy = std::floor(y);
  const float tx = x - fx, ty = y - fy;
  auto px = [&](int i, int j) {
    i = ((i % w) + w) % w;
    j = ((j % h) + h) % h;
    const cv::Vec3f& p = image.at<cv::Vec3f>(j, i);
    return Eigen::Vector3f(p[0], p[1], p[2]);
  };
  const int ix = static_cast<int>(fx), iy = static_cast<int>(fy);
  return (1 - ty) * ((1 - tx) * px(ix, iy) + tx * px(ix + 1, iy)) +
         ty * ((1 - tx) * px(ix, iy + 1) + tx * px(ix + 1, iy + 1));
}

float procedural_pattern(const scene::Texture& t, float u, float v, float footprint) {
  using scene::TextureKind;
  switch (t.kind) {
    case TextureKind::kChecker:
      return static_cast<float>(
          (static_cast<long>(std::floor(u)) + static_cast<long>(std::floor(v))) & 1);
    case TextureKind::kStripes:
      // Soft-edged stripes across u.
      return std::clamp(0.5f + 2.0f * std::sin(kTwoPi * u), 0.0f, 1.0f);
    case TextureKind::kNoise:
      return fbm(t.seed, u, v, footprint);
    case TextureKind::kFabric: {
      // Plain weave: alternate cells carry warp or weft threads, each with a round profile.
      const bool warp =
          ((static_cast<long>(std::floor(u)) + static_cast<long>(std::floor(v))) & 1) != 0;
      const float across = warp ? fract(u * 4.0f) : fract(v * 4.0f);
      // Threads finer than the pixel fade to their mean profile, 2/π.
      const float w = detail_weight(footprint, 4.0f);
      const float thread = w * std::sin(std::numbers::pi_v<float> * across) +
                           (1.0f - w) * (2.0f / std::numbers::pi_v<float>);
      return std::clamp(
          0.8f * thread + 0.2f * t.turbulence * fbm(t.seed, u * 8, v * 8, footprint * 8), 0.0f,
          1.0f);
    }
    case TextureKind::kWood: {
      // Growth rings around an axis near the texture's corner, warped by noise.
      const float r = std::sqrt((u + 0.3f) * (u + 0.3f) + 0.1f * (v * v));
      const float ring = fract(r + 0.3f * t.turbulence * fbm(t.seed, u * 2, v * 2, footprint * 2));
      return ring * ring * ring;
    }
    case TextureKind::kMarble:
      return 0.5f + 0.5f * std::sin(kTwoPi * 0.5f * (u + v) +
                                    4.0f * t.turbulence * fbm(t.seed, u, v, footprint));
    case TextureKind::kNone:
    case TextureKind::kImage:
    case TextureKind::kImageDetail:
      break;
  }
  return 0.0f;
}

Eigen::Matrix3f hue_rotation(float degrees) {
  // Rodrigues rotation about the unit grey axis g = (1, 1, 1)/√3:
  // R = cos a · I + sin a · [g]× + (1 − cos a) · g gᵀ.
  const float a = degrees * std::numbers::pi_v<float> / 180.0f;
  const Eigen::Vector3f g = Eigen::Vector3f::Constant(1.0f / std::sqrt(3.0f));
  Eigen::Matrix3f cross;
  cross << 0, -g.z(), g.y(), g.z(), 0, -g.x(), -g.y(), g.x(), 0;
  return std::cos(a) * Eigen::Matrix3f::Identity() + std::sin(a) * cross +
         (1.0f - std::cos(a)) * g * g.transpose();
}

Eigen::Vector3f rotate_hue(const Eigen::Vector3f& rgb, float degrees) {
  if (degrees == 0.0f) return rgb;
  return (hue_rotation(degrees) * rgb).cwiseMax(0.0f);
}

TextureSampler::TextureSampler(const scene::Texture& texture, const std::string& resolved_path,
                               const std::string& what)
    : texture_(texture) {
  if (texture.kind == scene::TextureKind::kImage) image_ = load_linear_image(resolved_path, what);
  if (texture.kind == scene::TextureKind::kImageDetail) {
    image_ = load_detail_image(resolved_path, what);
  }
}

bool TextureSampler::filters_detail() const {
  using scene::TextureKind;
  return texture_.kind == TextureKind::kNoise || texture_.kind == TextureKind::kFabric ||
         texture_.kind == TextureKind::kWood || texture_.kind == TextureKind::kMarble;
}

Eigen::Vector3f TextureSampler::at(float u, float v, float footprint) const {
  if (texture_.kind == scene::TextureKind::kNone) return Eigen::Vector3f::Ones();
  if (texture_.kind == scene::TextureKind::kImage) return sample_bilinear(image_, u, 1.0f - v);
  if (texture_.kind == scene::TextureKind::kImageDetail) {
    return sample_bilinear(image_, u * texture_.scale, 1.0f - v * texture_.scale);
  }
  const float t = procedural_pattern(texture_, u * texture_.scale, v * texture_.scale,
                                     footprint * texture_.scale);
  return texture_.color_a + t * (texture_.color_b - texture_.color_a);
}

}  // namespace wheelpose::render
