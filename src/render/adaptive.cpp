#include "render/adaptive.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "core/cpu_clones.h"
#include "core/error.h"

namespace wheelpose::render {

namespace {

// The renderer's own reuse threshold: beyond ≈ 18° a later sample is lit on its own anyway.
constexpr float kMinNormalCos = 0.95f;
constexpr float kMaxPlaneSine = 0.5f;  // sin 30°

// The four neighbours after a pixel in reading order; with the four before it (whose own
// forward pairs point back at it) they make the 8-neighbourhood.
constexpr int kForward[4][2] = {{1, 0}, {-1, 1}, {0, 1}, {1, 1}};

// Pointers to the planes from one pixel on.
struct PlanesAt {
  const int* surface;
  const float* n[3];
  const float* p[3];
  const float* color[3];
};

PlanesAt planes_at(const GuidePlanes& g, const std::vector<float> (&color)[3], std::size_t i) {
  return {g.surface.data() + i,
          {g.geometry[0].data() + i, g.geometry[1].data() + i, g.geometry[2].data() + i},
          {g.geometry[3].data() + i, g.geometry[4].data() + i, g.geometry[5].data() + i},
          {color[0].data() + i, color[1].data() + i, color[2].data() + i}};
}

// For `count` pixel pairs (a[x], b[x]), sets `bit` in bits[x] when they lie on different sides
// of an edge: another surface, a colour step above `contrast`, or, on a lit surface, normals
// more than ≈ 18° apart or either point more than 30° off the other's tangent plane. Written
// without branches so the compiler can vectorise it; built for AVX2 too, like the denoise loop
// (independent lanes, no FMA: both builds give the same bits).
WHEELPOSE_LOOP_BODY void edge_bits_lanes(int count, const PlanesAt& a, const PlanesAt& b,
                                         float contrast, int bit, std::uint8_t* __restrict bits) {
  constexpr float kPlane2 = kMaxPlaneSine * kMaxPlaneSine;
  for (int x = 0; x < count; ++x) {
    const int colour = static_cast<int>(std::abs(a.color[0][x] - b.color[0][x]) > contrast) |
                       static_cast<int>(std::abs(a.color[1][x] - b.color[1][x]) > contrast) |
                       static_cast<int>(std::abs(a.color[2][x] - b.color[2][x]) > contrast);
    const float anx = a.n[0][x], any = a.n[1][x], anz = a.n[2][x];
    const float bnx = b.n[0][x], bny = b.n[1][x], bnz = b.n[2][x];
    const float agree = anx * bnx + any * bny + anz * bnz;
    const float sx = b.p[0][x] - a.p[0][x], sy = b.p[1][x] - a.p[1][x], sz = b.p[2][x] - a.p[2][x];
    const float len2 = sx * sx + sy * sy + sz * sz;
    const float off_a = anx * sx + any * sy + anz * sz;
    const float off_b = bnx * sx + bny * sy + bnz * sz;
    const int shape = static_cast<int>(agree < kMinNormalCos) |
                      static_cast<int>(off_a * off_a > kPlane2 * len2) |
                      static_cast<int>(off_b * off_b > kPlane2 * len2);
    // The background (surface −1) compares by colour only.
    const int edge = static_cast<int>(a.surface[x] != b.surface[x]) | colour |
                     (static_cast<int>(a.surface[x] >= 0) & shape);
    bits[x] = static_cast<std::uint8_t>(bits[x] | (edge << bit));
  }
}
WHEELPOSE_AVX2_COPY(edge_bits, edge_bits_lanes)

}  // namespace

void mark_edges(int width, int height, const std::vector<LightingGuide>& guide,
                const std::vector<std::array<float, 3>>& color, float contrast,
                std::vector<std::uint8_t>& refine) {
  GuidePlanes planes;
  planes.assign(guide);
  std::vector<float> color_planes[3];
  for (int c = 0; c < 3; ++c) {
    color_planes[c].reserve(color.size());
    for (const auto& rgb : color) color_planes[c].push_back(rgb[c]);
  }
  mark_edges(width, height, planes, color_planes, contrast, refine);
}

void mark_edges(int width, int height, const GuidePlanes& guide,
                const std::vector<float> (&color)[3], float contrast,
                std::vector<std::uint8_t>& refine) {
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  WHEELPOSE_CHECK(width >= 0 && height >= 0 && guide.size() == n);
  for (const auto& plane : color) WHEELPOSE_CHECK(plane.size() == n);
  // Pass 1: bit d of edges[i] = an edge between pixel i and its forward neighbour d. Each pair
  // is tested once; pass 2 gathers both directions, so no pixel is written by two threads.
  std::vector<std::uint8_t> edges(n, 0);
  tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y < rows.end(); ++y) {
      const std::size_t row = static_cast<std::size_t>(y) * width;
      for (int d = 0; d < 4; ++d) {
        const int dx = kForward[d][0], dy = kForward[d][1];
        if (y + dy >= height) continue;
        // Pixels x of this row whose forward neighbour (x + dx, y + dy) exists.
        const int x0 = std::max(0, -dx), x1 = std::min(width, width - dx);
        if (x1 <= x0) continue;
        const std::size_t first = row + x0;
        const std::size_t neighbour = first + static_cast<std::size_t>(dy) * width + dx;
        edge_bits(x1 - x0, planes_at(guide, color, first), planes_at(guide, color, neighbour),
                  contrast, d, edges.data() + first);
      }
    }
  });
  refine.resize(n);
  tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y < rows.end(); ++y) {
      const std::size_t row = static_cast<std::size_t>(y) * width;
      std::uint8_t* out = refine.data() + row;
      const std::uint8_t* own = edges.data() + row;
      for (int x = 0; x < width; ++x) out[x] = own[x] != 0;
      // Pairs of which this pixel is the forward end: bit d of the pixel (x, y) − forward[d].
      for (int d = 0; d < 4; ++d) {
        const int dx = kForward[d][0], dy = kForward[d][1];
        if (y - dy < 0) continue;
        const int x0 = std::max(0, dx), x1 = std::min(width, width + dx);
        // From the first pixel that has this back neighbour, so no pointer precedes the array.
        const std::uint8_t* back =
            edges.data() + (row - static_cast<std::size_t>(dy) * width + x0 - dx);
        for (int k = 0; k < x1 - x0; ++k)
          out[x0 + k] = static_cast<std::uint8_t>(out[x0 + k] | ((back[k] >> d) & 1u));
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
