#include "learn/movenet_targets.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace wheelpose::learn {
namespace {

// Max-merges exp(-d²/2σ²) around (cy, cx) into one channel of an NHWC map, 3σ wide.
void splat(std::vector<float>& map, int grid, int channels, int channel, int cy, int cx,
           double sigma) {
  const int radius = static_cast<int>(std::ceil(3 * sigma));
  for (int y = std::max(0, cy - radius); y <= std::min(grid - 1, cy + radius); ++y) {
    for (int x = std::max(0, cx - radius); x <= std::min(grid - 1, cx + radius); ++x) {
      const double d2 = (y - cy) * (y - cy) + (x - cx) * (x - cx);
      const float value = static_cast<float>(std::exp(-d2 / (2 * sigma * sigma)));
      float& cell = map[(static_cast<std::size_t>(y) * grid + x) * channels + channel];
      cell = std::max(cell, value);
    }
  }
}

}  // namespace

MovenetTargets build_targets(const std::vector<TrainPerson>& people, int input_size) {
  WHEELPOSE_CHECK(input_size % kOutputStride == 0);
  MovenetTargets t;
  t.grid = input_size / kOutputStride;
  const int g = t.grid;
  t.centre_heatmap.assign(static_cast<std::size_t>(g) * g, 0.f);
  t.keypoint_heatmap.assign(static_cast<std::size_t>(g) * g * kKeypoints, 0.f);
  const double s = 1.0 / kOutputStride;
  for (const TrainPerson& p : people) {
    if (p.ignore) continue;
    const double cy = (p.box.y + p.box.h / 2) * s, cx = (p.box.x + p.box.w / 2) * s;
    const int iy = std::clamp(static_cast<int>(std::floor(cy)), 0, g - 1);
    const int ix = std::clamp(static_cast<int>(std::floor(cx)), 0, g - 1);
    const double sigma = std::max(0.8, 0.1 * std::sqrt(p.box.h * s * p.box.w * s));
    splat(t.centre_heatmap, g, 1, 0, iy, ix, sigma);
    CentreTarget c;
    c.cell = iy * g + ix;
    c.scale = {static_cast<float>(p.box.h * s), static_cast<float>(p.box.w * s)};
    c.offset = {static_cast<float>(cy - iy), static_cast<float>(cx - ix)};
    for (int k = 0; k < kKeypoints; ++k) {
      if (p.keypoints[3 * k + 2] <= 0) continue;
      const double ky = p.keypoints[3 * k + 1] * s, kx = p.keypoints[3 * k] * s;
      c.regress[2 * k] = static_cast<float>(ky - iy);
      c.regress[2 * k + 1] = static_cast<float>(kx - ix);
      c.regress_mask[k] = 1;
      const int ky_cell = std::clamp(static_cast<int>(std::floor(ky)), 0, g - 1);
      const int kx_cell = std::clamp(static_cast<int>(std::floor(kx)), 0, g - 1);
      splat(t.keypoint_heatmap, g, kKeypoints, k, ky_cell, kx_cell, sigma);
      t.keypoints.push_back({ky_cell * g + kx_cell,
                             k,
                             {static_cast<float>(ky - ky_cell), static_cast<float>(kx - kx_cell)}});
    }
    t.centres.push_back(c);
  }
  for (const TrainPerson& p : people) {
    if (!p.ignore) continue;
    if (t.heatmap_weight.empty()) t.heatmap_weight.assign(static_cast<std::size_t>(g) * g, 1.f);
    // Every cell the region's box touches, unless a person's centre is spread there.
    const int y0 = std::clamp(static_cast<int>(std::floor(p.box.y * s)), 0, g - 1);
    const int x0 = std::clamp(static_cast<int>(std::floor(p.box.x * s)), 0, g - 1);
    const int y1 = std::clamp(static_cast<int>(std::ceil((p.box.y + p.box.h) * s)) - 1, 0, g - 1);
    const int x1 = std::clamp(static_cast<int>(std::ceil((p.box.x + p.box.w) * s)) - 1, 0, g - 1);
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        const std::size_t cell = static_cast<std::size_t>(y) * g + x;
        if (t.centre_heatmap[cell] == 0.f) t.heatmap_weight[cell] = 0.f;
      }
    }
  }
  return t;
}

}  // namespace wheelpose::learn
