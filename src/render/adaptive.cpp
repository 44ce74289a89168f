#include "render/adaptive.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "core/error.h"

namespace wheelpose::render {

namespace {

// The renderer's own reuse threshold: beyond ≈ 18° a later sample is lit on its own anyway.
constexpr float kMinNormalCos = 0.95f;
constexpr float kMaxPlaneSine = 0.5f;  // sin 30°

// q lies off c's tangent plane by more than kMaxPlaneSine (compared squared, no root).
bool off_plane(const LightingGuide& c, float sx, float sy, float sz) {
  const float off = c.normal[0] * sx + c.normal[1] * sy + c.normal[2] * sz;
  return off * off > kMaxPlaneSine * kMaxPlaneSine * (sx * sx + sy * sy + sz * sz);
}

// Whether two neighbouring pixels are on different sides of an edge (symmetric).
bool edge_between(const LightingGuide& a, const std::array<float, 3>& a_color,
                  const LightingGuide& b, const std::array<float, 3>& b_color, float contrast) {
  if (a.surface != b.surface) return true;
  for (int k = 0; k < 3; ++k) {
    if (std::abs(a_color[k] - b_color[k]) > contrast) return true;
  }
  if (a.surface < 0) return false;  // background: colour only
  const float agree =
      a.normal[0] * b.normal[0] + a.normal[1] * b.normal[1] + a.normal[2] * b.normal[2];
  if (agree < kMinNormalCos) return true;
  const float sx = b.position[0] - a.position[0], sy = b.position[1] - a.position[1],
              sz = b.position[2] - a.position[2];
  return off_plane(a, sx, sy, sz) || off_plane(b, sx, sy, sz);
}

// The four neighbours after a pixel in reading order; with the four before it (whose own
// forward pairs point back at it) they make the 8-neighbourhood.
constexpr int kForward[4][2] = {{1, 0}, {-1, 1}, {0, 1}, {1, 1}};

}  // namespace

void mark_edges(int width, int height, const std::vector<LightingGuide>& guide,
                const std::vector<std::array<float, 3>>& color, float contrast,
                std::vector<std::uint8_t>& refine) {
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  WHEELPOSE_CHECK(width >= 0 && height >= 0 && guide.size() == n && color.size() == n);
  // Pass 1: bit d of edges[i] = an edge between pixel i and its forward neighbour d. Each pair
  // is tested once; pass 2 gathers both directions, so no pixel is written by two threads.
  std::vector<std::uint8_t> edges(n, 0);
  tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y < rows.end(); ++y) {
      for (int x = 0; x < width; ++x) {
        const std::size_t i = static_cast<std::size_t>(y) * width + x;
        std::uint8_t bits = 0;
        for (int d = 0; d < 4; ++d) {
          const int qx = x + kForward[d][0], qy = y + kForward[d][1];
          if (qx < 0 || qx >= width || qy >= height) continue;
          const std::size_t j = static_cast<std::size_t>(qy) * width + qx;
          if (edge_between(guide[i], color[i], guide[j], color[j], contrast)) bits |= 1u << d;
        }
        edges[i] = bits;
      }
    }
  });
  refine.resize(n);
  tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y < rows.end(); ++y) {
      for (int x = 0; x < width; ++x) {
        const std::size_t i = static_cast<std::size_t>(y) * width + x;
        bool edge = edges[i] != 0;
        // Pairs of which this pixel is the forward end.
        for (int d = 0; d < 4 && !edge; ++d) {
          const int px = x - kForward[d][0], py = y - kForward[d][1];
          if (px < 0 || px >= width || py < 0) continue;
          edge = (edges[static_cast<std::size_t>(py) * width + px] >> d) & 1u;
        }
        refine[i] = edge ? 1 : 0;
      }
    }
  });
}

void find_slivers(const scene::Projector& projector, const float* vertices,
                  const std::vector<Eigen::Vector3i>& triangles, std::vector<Sliver>& out) {
  constexpr float kNear = 1e-3f;
  // Far off-screen endpoints would overflow cv::Point; such lines cannot cross the screen.
  const float limit = 4.0f * static_cast<float>(std::max(projector.width, projector.height)) + 1e4f;
  // Each vertex projected once (NaN marks one behind the camera), then read per triangle.
  int vertex_count = 0;
  for (const Eigen::Vector3i& tri : triangles)
    vertex_count = std::max(vertex_count, tri.maxCoeff() + 1);
  std::vector<Eigen::Vector2f> projected(static_cast<std::size_t>(vertex_count));
  for (int v = 0; v < vertex_count; ++v) {
    const Eigen::Vector3f cam =
        projector.to_camera(Eigen::Map<const Eigen::Vector3f>(vertices + 3 * v));
    projected[v] = cam.z() < -kNear
                       ? projector.project(cam)
                       : Eigen::Vector2f::Constant(std::numeric_limits<float>::quiet_NaN());
  }
  for (const Eigen::Vector3i& tri : triangles) {
    const Eigen::Vector2f p[3] = {projected[tri[0]], projected[tri[1]], projected[tri[2]]};
    if (std::isnan(p[0].x()) || std::isnan(p[1].x()) || std::isnan(p[2].x())) continue;
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
    if (from.cwiseAbs().maxCoeff() > limit || to.cwiseAbs().maxCoeff() > limit) continue;
    auto pixel = [](const Eigen::Vector2f& q) {
      return cv::Point(static_cast<int>(std::lround(q.x())), static_cast<int>(std::lround(q.y())));
    };
    out.push_back({pixel(from), pixel(to)});
  }
}

void mark_slivers(const std::vector<Sliver>& slivers, int width, int height,
                  std::vector<std::uint8_t>& refine) {
  WHEELPOSE_CHECK(refine.size() ==
                  static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
  cv::Mat mask(height, width, CV_8U, refine.data());  // a view: lines are drawn into `refine`
  for (const Sliver& s : slivers) {
    cv::line(mask, s.from, s.to, cv::Scalar(1), 2, cv::LINE_8);  // thickness 2: a 3-pixel band
  }
}

}  // namespace wheelpose::render
