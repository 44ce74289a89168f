#include "learn/movenet_targets.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>

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

MovenetTargets build_targets(const std::vector<TrainPerson>& people, int input_size,
                             int offset_radius) {
  WHEELPOSE_CHECK(offset_radius >= 0);
  WHEELPOSE_CHECK(input_size % kOutputStride == 0);
  MovenetTargets t;
  t.grid = input_size / kOutputStride;
  const int g = t.grid;
  t.centre_heatmap.assign(static_cast<std::size_t>(g) * g, 0.f);
  t.keypoint_heatmap.assign(static_cast<std::size_t>(g) * g * kKeypoints, 0.f);
  const double s = 1.0 / kOutputStride;
  // (cell · 17 + keypoint) → its entry in t.keypoints, for the cells around keypoints: a cell
  // keeps the heaviest (nearest) target. Two keypoints' own cells (weight 1) both stay.
  std::unordered_map<std::int64_t, std::size_t> around;
  auto add_offset = [&](const KeypointTarget& target) {
    const std::int64_t key = static_cast<std::int64_t>(target.cell) * kKeypoints + target.keypoint;
    const auto [it, fresh] = around.try_emplace(key, t.keypoints.size());
    if (fresh) {
      t.keypoints.push_back(target);
      return;
    }
    KeypointTarget& held = t.keypoints[it->second];
    if (target.weight == 1 && held.weight == 1) {
      t.keypoints.push_back(target);
    } else if (target.weight > held.weight) {
      held = target;
    }
  };
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
      const int r = offset_radius;
      for (int y = std::max(0, ky_cell - r); y <= std::min(g - 1, ky_cell + r); ++y) {
        for (int x = std::max(0, kx_cell - r); x <= std::min(g - 1, kx_cell + r); ++x) {
          const double d2 = (y - ky_cell) * (y - ky_cell) + (x - kx_cell) * (x - kx_cell);
          add_offset({y * g + x,
                      k,
                      {static_cast<float>(ky - y), static_cast<float>(kx - x)},
                      static_cast<float>(std::exp(-d2 / (2 * sigma * sigma)))});
        }
      }
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
