#include "render/adaptive.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "core/error.h"

namespace wheelpose::render {

namespace {

// The renderer's own reuse threshold: beyond ≈ 18° a later sample is lit on its own anyway.
constexpr float kMinNormalCos = 0.95f;
constexpr float kMaxPlaneSine = 0.5f;  // sin 30°

bool differs(const LightingGuide& c, const std::array<float, 3>& c_color, const LightingGuide& q,
             const std::array<float, 3>& q_color, float contrast) {
  if (q.surface != c.surface) return true;
  for (int k = 0; k < 3; ++k) {
    if (std::abs(q_color[k] - c_color[k]) > contrast) return true;
  }
  if (c.surface < 0) return false;  // background: colour only
  const float agree =
      c.normal[0] * q.normal[0] + c.normal[1] * q.normal[1] + c.normal[2] * q.normal[2];
  if (agree < kMinNormalCos) return true;
  const float sx = q.position[0] - c.position[0], sy = q.position[1] - c.position[1],
              sz = q.position[2] - c.position[2];
  const float off = c.normal[0] * sx + c.normal[1] * sy + c.normal[2] * sz;
  return off * off > kMaxPlaneSine * kMaxPlaneSine * (sx * sx + sy * sy + sz * sz);
}

}  // namespace

long long mark_edges(int width, int height, const std::vector<LightingGuide>& guide,
                     const std::vector<std::array<float, 3>>& color, float contrast,
                     std::vector<std::uint8_t>& refine) {
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  WHEELPOSE_CHECK(width >= 0 && height >= 0 && guide.size() == n && color.size() == n);
  refine.resize(n);
  return tbb::parallel_reduce(
      tbb::blocked_range<int>(0, height), 0LL,
      [&](const tbb::blocked_range<int>& rows, long long marked) {
        for (int y = rows.begin(); y < rows.end(); ++y) {
          for (int x = 0; x < width; ++x) {
            const std::size_t i = static_cast<std::size_t>(y) * width + x;
            bool edge = false;
            for (int dy = -1; dy <= 1 && !edge; ++dy) {
              const int qy = y + dy;
              if (qy < 0 || qy >= height) continue;
              for (int dx = -1; dx <= 1 && !edge; ++dx) {
                const int qx = x + dx;
                if ((dx == 0 && dy == 0) || qx < 0 || qx >= width) continue;
                const std::size_t j = static_cast<std::size_t>(qy) * width + qx;
                // Tested from both sides: the tangent-plane test is not symmetric.
                edge = differs(guide[i], color[i], guide[j], color[j], contrast) ||
                       differs(guide[j], color[j], guide[i], color[i], contrast);
              }
            }
            refine[i] = edge ? 1 : 0;
            marked += edge;
          }
        }
        return marked;
      },
      [](long long a, long long b) { return a + b; });
}

void mark_slivers(const scene::Projector& projector, const float* vertices,
                  const std::vector<Eigen::Vector3i>& triangles,
                  std::vector<std::uint8_t>& refine) {
  constexpr float kNear = 1e-3f;
  const int w = projector.width, h = projector.height;
  WHEELPOSE_CHECK(refine.size() == static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
  cv::Mat mask(h, w, CV_8U, refine.data());  // a view: lines are drawn into `refine`
  for (const Eigen::Vector3i& tri : triangles) {
    Eigen::Vector2f p[3];
    bool in_front = true;
    for (int c = 0; c < 3 && in_front; ++c) {
      const Eigen::Vector3f cam =
          projector.to_camera(Eigen::Map<const Eigen::Vector3f>(vertices + 3 * tri[c]));
      in_front = cam.z() < -kNear;
      if (in_front) p[c] = projector.project(cam);
    }
    if (!in_front) continue;
    int longest = 0;
    float longest_len = 0;
    for (int e = 0; e < 3; ++e) {
      const float len = (p[(e + 1) % 3] - p[e]).norm();
      if (len > longest_len) longest_len = len, longest = e;
    }
    if (longest_len <= 2.0f) continue;  // small: the first samples find it or it is sub-pixel
    const Eigen::Vector2f a = p[1] - p[0], b = p[2] - p[0];
    const float height = std::abs(a.x() * b.y() - a.y() * b.x()) / longest_len;
    if (height >= 1.0f) continue;  // a pixel wide or more: edge detection sees it
    const Eigen::Vector2f& from = p[longest];
    const Eigen::Vector2f& to = p[(longest + 1) % 3];
    // Far off-screen endpoints would overflow cv::Point; such lines cannot be on screen anyway.
    const float limit = 4.0f * static_cast<float>(std::max(w, h)) + 1e4f;
    if (from.cwiseAbs().maxCoeff() > limit || to.cwiseAbs().maxCoeff() > limit) continue;
    cv::line(
        mask,
        cv::Point(static_cast<int>(std::lround(from.x())), static_cast<int>(std::lround(from.y()))),
        cv::Point(static_cast<int>(std::lround(to.x())), static_cast<int>(std::lround(to.y()))),
        cv::Scalar(1), 2, cv::LINE_8);  // thickness 2: a 3-pixel band
  }
}

}  // namespace wheelpose::render
