#include "render/denoise.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "core/cpu_clones.h"
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

// Pointers to the planes of one row of pixels.
struct RowPlanes {
  const int* surface;
  const float* geometry[6];  // normal x, y, z, position x, y, z
  const float* light[6];
};

RowPlanes row_planes(const GuidePlanes& g, const std::vector<float> (&light)[6],
                     std::ptrdiff_t first) {
  RowPlanes r{g.surface.data() + first, {}, {}};
  for (int c = 0; c < 6; ++c) {
    r.geometry[c] = g.geometry[c].data() + first;
    r.light[c] = light[c].data() + first;
  }
  return r;
}

// Adds, for `count` pixels, the weighted light of the neighbour at the same index of the q_*
// planes (the centre planes shifted by the tap offset) into the sums. Restrict parameters and
// no branches let the compiler vectorise the loop. Built for AVX2 too (8 lanes, core/cpu_clones.h,
// chosen by the active ISA): lanes are independent and no FMA is formed, so both give the same
// bits.
WHEELPOSE_LOOP_BODY void accumulate_tap_lanes(
    int count, float kernel_weight, const int* __restrict c_surface, const float* __restrict nx,
    const float* __restrict ny, const float* __restrict nz, const float* __restrict px,
    const float* __restrict py, const float* __restrict pz, const int* __restrict q_surface,
    const float* __restrict q_nx, const float* __restrict q_ny, const float* __restrict q_nz,
    const float* __restrict q_px, const float* __restrict q_py, const float* __restrict q_pz,
    const float* __restrict l0, const float* __restrict l1, const float* __restrict l2,
    const float* __restrict l3, const float* __restrict l4, const float* __restrict l5,
    float* __restrict w_sum, float* __restrict s0, float* __restrict s1, float* __restrict s2,
    float* __restrict s3, float* __restrict s4, float* __restrict s5) {
  constexpr float kPlane2 = kPlaneSine * kPlaneSine, kMaxPlane2 = kMaxPlaneSine * kMaxPlaneSine;
  constexpr float kTiny = 1e-30f;  // keeps 0 / 0 (coincident points) at a ratio of 1
  for (int x = 0; x < count; ++x) {
    const float agree = nx[x] * q_nx[x] + ny[x] * q_ny[x] + nz[x] * q_nz[x];
    const float sx = q_px[x] - px[x], sy = q_py[x] - py[x], sz = q_pz[x] - pz[x];
    const float len2 = sx * sx + sy * sy + sz * sz;
    const float off = nx[x] * sx + ny[x] * sy + nz[x] * sz;
    const float off2 = off * off;
    // 0 when they must not mix: another surface, a crease, or off the tangent plane.
    const int mixes = static_cast<int>(q_surface[x] == c_surface[x]) &
                      static_cast<int>(agree >= kMinNormalCos) &
                      static_cast<int>(off2 <= kMaxPlane2 * len2);
    // agree² / (1 + off² / (len² · kPlaneSine²)), written without a branch.
    const float weight = static_cast<float>(mixes) * kernel_weight * agree * agree *
                         (len2 * kPlane2 + kTiny) / (len2 * kPlane2 + off2 + kTiny);
    w_sum[x] += weight;
    s0[x] += weight * l0[x];
    s1[x] += weight * l1[x];
    s2[x] += weight * l2[x];
    s3[x] += weight * l3[x];
    s4[x] += weight * l4[x];
    s5[x] += weight * l5[x];
  }
}
WHEELPOSE_AVX2_COPY(accumulate_tap, accumulate_tap_lanes)

// One 1-D pass over planes `in` into `out`: along rows (along_x) or columns.
void filter_pass(const GuidePlanes& g, const std::vector<float>& kernel, int w, int h, bool along_x,
                 const std::vector<float> (&in)[6], std::vector<float> (&out)[6]) {
  const int radius = static_cast<int>(kernel.size()) - 1;
  tbb::parallel_for(tbb::blocked_range<int>(0, h), [&](const tbb::blocked_range<int>& rows) {
    std::vector<float> sums(7 * static_cast<std::size_t>(w));
    float* s[7];
    for (int c = 0; c < 7; ++c) s[c] = sums.data() + c * static_cast<std::size_t>(w);
    for (int y = rows.begin(); y < rows.end(); ++y) {
      std::fill(sums.begin(), sums.end(), 0.0f);
      const std::ptrdiff_t row = static_cast<std::ptrdiff_t>(y) * w;
      const RowPlanes c = row_planes(g, in, row);
      for (int d = -radius; d <= radius; ++d) {
        // Pixels x of this row whose neighbour at offset d exists.
        int x0 = 0, x1 = w;
        std::ptrdiff_t step = d;
        if (along_x) {
          x0 = std::max(0, -d);
          x1 = std::min(w, w - d);
        } else {
          if (y + d < 0 || y + d >= h) continue;
          step = static_cast<std::ptrdiff_t>(d) * w;
        }
        if (x1 <= x0) continue;
        // Planes from the first pixel that has this neighbour on, so no pointer ever points
        // before an array.
        const RowPlanes c0 = row_planes(g, in, row + x0);
        const RowPlanes q = row_planes(g, in, row + step + x0);
        accumulate_tap(x1 - x0, kernel[d < 0 ? -d : d], c0.surface, c0.geometry[0], c0.geometry[1],
                       c0.geometry[2], c0.geometry[3], c0.geometry[4], c0.geometry[5], q.surface,
                       q.geometry[0], q.geometry[1], q.geometry[2], q.geometry[3], q.geometry[4],
                       q.geometry[5], q.light[0], q.light[1], q.light[2], q.light[3], q.light[4],
                       q.light[5], s[6] + x0, s[0] + x0, s[1] + x0, s[2] + x0, s[3] + x0, s[4] + x0,
                       s[5] + x0);
      }
      for (int x = 0; x < w; ++x) {
        // The centre always counts (weight ≈ 1), so a lit pixel's sum of weights is > 0.
        const bool lit = c.surface[x] >= 0;
        const float inv = lit ? 1.0f / s[6][x] : 0.0f;
        for (int k = 0; k < 6; ++k) out[k][row + x] = lit ? s[k][x] * inv : c.light[k][x];
      }
    }
  });
}

}  // namespace

void GuidePlanes::resize(std::size_t n) {
  surface.resize(n);
  for (auto& plane : geometry) plane.resize(n);
}

void GuidePlanes::assign(const std::vector<LightingGuide>& guide) {
  const std::size_t n = guide.size();
  resize(n);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t i = r.begin(); i < r.end(); ++i) {
                        surface[i] = guide[i].surface;
                        for (int c = 0; c < 3; ++c) {
                          geometry[c][i] = guide[i].normal[c];
                          geometry[3 + c][i] = guide[i].position[c];
                        }
                      }
                    });
}

void denoise_lighting(int width, int height, const std::vector<LightingGuide>& guide, int radius,
                      std::vector<PixelLight>& light, DenoiseScratch* scratch) {
  DenoiseScratch local;
  DenoiseScratch& s = scratch ? *scratch : local;
  s.guide.assign(guide);
  denoise_lighting(width, height, s.guide, radius, light, s);
}

void denoise_lighting(int width, int height, const GuidePlanes& guide, int radius,
                      std::vector<PixelLight>& light, DenoiseScratch& s) {
  WHEELPOSE_CHECK(radius >= 0 && width >= 0 && height >= 0);
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  WHEELPOSE_CHECK(guide.size() == n && light.size() == n);
  if (radius == 0 || n == 0) return;
  std::vector<float> kernel(static_cast<std::size_t>(radius) + 1);
  const float sigma = 0.5f * static_cast<float>(radius);
  for (int d = 0; d <= radius; ++d)
    kernel[d] = std::exp(-static_cast<float>(d * d) / (2 * sigma * sigma));
  for (int c = 0; c < 6; ++c) {
    s.light[c].resize(n);
    s.rows_done[c].resize(n);
  }
  // Planes in, planes out: every entry is written.
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t i = r.begin(); i < r.end(); ++i) {
                        for (int c = 0; c < 3; ++c) {
                          s.light[c][i] = light[i].diffuse[c];
                          s.light[3 + c][i] = light[i].specular[c];
                        }
                      }
                    });
  filter_pass(guide, kernel, width, height, true, s.light, s.rows_done);
  filter_pass(guide, kernel, width, height, false, s.rows_done, s.light);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t i = r.begin(); i < r.end(); ++i) {
                        for (int c = 0; c < 3; ++c) {
                          light[i].diffuse[c] = s.light[c][i];
                          light[i].specular[c] = s.light[3 + c][i];
                        }
                      }
                    });
}

}  // namespace wheelpose::render
