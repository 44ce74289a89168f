#include "render/denoise.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace wheelpose::render {

namespace {

// Normals more than ≈ 26° apart (cosine below this) never mix: creases and box edges stay sharp.
constexpr float kMinNormalCos = 0.9f;
// Tangent-plane test on the sine of the angle between the step to the neighbour and the centre's
// tangent plane, |n · (x_q − x_p)| / ‖x_q − x_p‖: the weight halves at kPlaneSine and is 0 from
// kMaxPlaneSine on (a step in depth, e.g. an arm in front of the torso of the same mesh).
constexpr float kPlaneSine = 0.15f;
constexpr float kMaxPlaneSine = 0.5f;

// Weight of neighbour q for centre c (0 when they must not mix), before the spatial kernel.
float edge_weight(const LightingGuide& c, const LightingGuide& q) {
  if (q.surface != c.surface) return 0.0f;
  const float agree =
      c.normal[0] * q.normal[0] + c.normal[1] * q.normal[1] + c.normal[2] * q.normal[2];
  if (agree < kMinNormalCos) return 0.0f;
  const float sx = q.position[0] - c.position[0], sy = q.position[1] - c.position[1],
              sz = q.position[2] - c.position[2];
  const float len2 = sx * sx + sy * sy + sz * sz;
  const float off = c.normal[0] * sx + c.normal[1] * sy + c.normal[2] * sz;
  // Compared squared, without a square root.
  if (off * off > kMaxPlaneSine * kMaxPlaneSine * len2) return 0.0f;
  const float t = len2 > 0 ? off * off / (len2 * (kPlaneSine * kPlaneSine)) : 0.0f;
  return agree * agree / (1.0f + t);
}

// One 1-D pass along rows (along_x) or columns from `in` into `out`.
void filter_pass(const std::vector<LightingGuide>& guide, const std::vector<float>& kernel, int w,
                 int h, bool along_x, const std::vector<PixelLight>& in,
                 std::vector<PixelLight>& out) {
  const int radius = static_cast<int>(kernel.size()) - 1;
  const std::ptrdiff_t stride = along_x ? 1 : w;
  tbb::parallel_for(tbb::blocked_range<int>(0, h), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y < rows.end(); ++y) {
      for (int x = 0; x < w; ++x) {
        const std::ptrdiff_t i = static_cast<std::ptrdiff_t>(y) * w + x;
        const LightingGuide& c = guide[i];
        if (c.surface < 0) {
          out[i] = in[i];
          continue;
        }
        const int at = along_x ? x : y, size = along_x ? w : h;
        float sum[6] = {0, 0, 0, 0, 0, 0};
        float w_sum = 0;
        for (int d = -std::min(radius, at); d <= std::min(radius, size - 1 - at); ++d) {
          const std::ptrdiff_t j = i + d * stride;
          const float weight = kernel[d < 0 ? -d : d] * edge_weight(c, guide[j]);
          if (weight <= 0) continue;
          const PixelLight& q = in[j];
          for (int k = 0; k < 3; ++k) {
            sum[k] += weight * q.diffuse[k];
            sum[3 + k] += weight * q.specular[k];
          }
          w_sum += weight;
        }
        // The centre always counts (weight 1), so w_sum > 0.
        const float inv = 1.0f / w_sum;
        for (int k = 0; k < 3; ++k) {
          out[i].diffuse[k] = sum[k] * inv;
          out[i].specular[k] = sum[3 + k] * inv;
        }
      }
    }
  });
}

}  // namespace

void denoise_lighting(int width, int height, const std::vector<LightingGuide>& guide, int radius,
                      std::vector<PixelLight>& light, std::vector<PixelLight>* scratch) {
  WHEELPOSE_CHECK(radius >= 0 && width >= 0 && height >= 0);
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  WHEELPOSE_CHECK(guide.size() == n && light.size() == n);
  if (radius == 0 || n == 0) return;
  std::vector<float> kernel(static_cast<std::size_t>(radius) + 1);
  const float sigma = 0.5f * static_cast<float>(radius);
  for (int d = 0; d <= radius; ++d)
    kernel[d] = std::exp(-static_cast<float>(d * d) / (2 * sigma * sigma));
  std::vector<PixelLight> local;
  std::vector<PixelLight>& rows_done = scratch ? *scratch : local;
  rows_done.resize(n);  // every entry is written by the row pass
  filter_pass(guide, kernel, width, height, true, light, rows_done);
  filter_pass(guide, kernel, width, height, false, rows_done, light);
}

}  // namespace wheelpose::render
