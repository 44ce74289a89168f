#include "render/motion_blur.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace wheelpose::render {
namespace {

constexpr float kMaxHalf = kMaxMotionBlurPixels / 2;
constexpr int kMaxTile = 32;
constexpr float kFar = 1e4f;  // the depth of pixels that hit nothing

float length(const cv::Vec2f& v) { return std::hypot(v[0], v[1]); }

// Half the motion (a streak reaches half of it either side of the pixel), shortened to the cap.
cv::Vec2f half_motion(const cv::Vec2f& m) {
  cv::Vec2f h = 0.5f * m;
  const float len = length(h);
  if (len > kMaxHalf) h *= kMaxHalf / len;
  return h;
}

// 1 when depth `a` is not behind depth `b`, falling to 0 over a few percent of the depth.
float not_behind(float a, float b) {
  const float extent = 0.02f * std::min(a, b) + 0.01f;
  return std::clamp(1.0f - (a - b) / extent, 0.0f, 1.0f);
}

// A streak of half-length `radius` covers a point `dist` away with this weight.
float cone(float dist, float radius) {
  return radius <= 0 ? 0.0f : std::clamp(1.0f - dist / radius, 0.0f, 1.0f);
}
float cylinder(float dist, float radius) {
  if (radius <= 0) return dist <= 0 ? 1.0f : 0.0f;
  const float t = std::clamp((dist - 0.95f * radius) / (0.1f * radius), 0.0f, 1.0f);
  return 1.0f - t * t * (3 - 2 * t);
}

}  // namespace

cv::Mat motion_blur(const cv::Mat& linear, const cv::Mat& depth, const cv::Mat& motion) {
  if (motion.empty()) return linear.clone();
  CV_Assert(linear.type() == CV_32FC3 && depth.type() == CV_32F && motion.type() == CV_32FC2);
  CV_Assert(linear.size() == depth.size() && linear.size() == motion.size());
  const int w = linear.cols, h = linear.rows;
  cv::Mat half(h, w, CV_32FC2);
  float longest = 0;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const cv::Vec2f v = half_motion(motion.at<cv::Vec2f>(y, x));
      half.at<cv::Vec2f>(y, x) = v;
      longest = std::max(longest, length(v));
    }
  }
  if (longest < 0.5f) return linear.clone();

  // The longest motion in each tile, then in each tile's 3×3 neighbourhood: the direction in
  // which a pixel looks for what may cross it (tiles as wide as the longest half-streak).
  const int tile = std::clamp(static_cast<int>(std::ceil(longest)), 1, kMaxTile);
  const int tiles_x = (w + tile - 1) / tile, tiles_y = (h + tile - 1) / tile;
  std::vector<cv::Vec2f> tile_max(static_cast<std::size_t>(tiles_x * tiles_y), cv::Vec2f(0, 0));
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      cv::Vec2f& m = tile_max[static_cast<std::size_t>((y / tile) * tiles_x + x / tile)];
      const cv::Vec2f& v = half.at<cv::Vec2f>(y, x);
      if (length(v) > length(m)) m = v;
    }
  }
  std::vector<cv::Vec2f> neighbour_max(tile_max.size(), cv::Vec2f(0, 0));
  for (int ty = 0; ty < tiles_y; ++ty) {
    for (int tx = 0; tx < tiles_x; ++tx) {
      cv::Vec2f& m = neighbour_max[static_cast<std::size_t>(ty * tiles_x + tx)];
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const int nx = tx + dx, ny = ty + dy;
          if (nx < 0 || ny < 0 || nx >= tiles_x || ny >= tiles_y) continue;
          const cv::Vec2f& v = tile_max[static_cast<std::size_t>(ny * tiles_x + nx)];
          if (length(v) > length(m)) m = v;
        }
      }
    }
  }

  cv::Mat out = linear.clone();
  const auto depth_at = [&](int x, int y) {
    const float d = depth.at<float>(y, x);
    return d > 0 ? d : kFar;
  };
  cv::parallel_for_(cv::Range(0, h), [&](const cv::Range& rows) {
    for (int y = rows.start; y < rows.end; ++y) {
      for (int x = 0; x < w; ++x) {
        const cv::Vec2f n =
            neighbour_max[static_cast<std::size_t>((y / tile) * tiles_x + x / tile)];
        const float reach = length(n);
        if (reach < 0.5f) continue;
        const float own_radius = length(half.at<cv::Vec2f>(y, x));
        const float own_depth = depth_at(x, y);
        // Samples about a pixel apart along the streak, the pixel itself in the middle.
        const int count = std::min(2 * static_cast<int>(std::ceil(reach)) + 1, 65);
        const float own_weight = static_cast<float>(count - 1) / 4;
        cv::Vec3f sum(0, 0, 0);
        float gathered = 0;
        for (int i = 0; i < count; ++i) {
          if (2 * i == count - 1) continue;
          const float t = -1.0f + 2.0f * static_cast<float>(i) / static_cast<float>(count - 1);
          const int sx = std::clamp(static_cast<int>(std::lround(x + t * n[0])), 0, w - 1);
          const int sy = std::clamp(static_cast<int>(std::lround(y + t * n[1])), 0, h - 1);
          const float dist = std::abs(t) * reach;
          const float radius = length(half.at<cv::Vec2f>(sy, sx));
          const float sample_depth = depth_at(sx, sy);
          // A sample in front smears over this pixel as far as its own streak reaches; a sample
          // behind shows through as far as this pixel's streak reaches; two moving surfaces at
          // one depth blur into each other.
          const float weight = not_behind(sample_depth, own_depth) * cone(dist, radius) +
                               not_behind(own_depth, sample_depth) * cone(dist, own_radius) +
                               2 * cylinder(dist, radius) * cylinder(dist, own_radius);
          sum += linear.at<cv::Vec3f>(sy, sx) * weight;
          gathered += weight;
        }
        // Nothing crosses the pixel: it keeps its exact value.
        if (gathered <= 0) continue;
        out.at<cv::Vec3f>(y, x) =
            (sum + linear.at<cv::Vec3f>(y, x) * own_weight) / (gathered + own_weight);
      }
    }
  });
  return out;
}

}  // namespace wheelpose::render
