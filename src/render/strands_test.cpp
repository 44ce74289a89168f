#include "render/strands.h"

#include <gtest/gtest.h>

#include <cmath>

namespace wheelpose::render {
namespace {

// Share of a UV patch the strands cover, sampled on a fine grid.
double covered_share(float per_uv, float coverage) {
  int covered = 0, total = 0;
  for (int i = 0; i < 400; ++i) {
    for (int j = 0; j < 400; ++j) {
      total += 1;
      covered += strand_at(0.1f + i * 0.002f, 0.2f + j * 0.002f, per_uv, coverage).covered;
    }
  }
  return static_cast<double>(covered) / total;
}

TEST(Strands, CoverTheRequestedShareOfTheCard) {
  EXPECT_NEAR(covered_share(120, 0.3f), 0.3, 0.02);
  EXPECT_NEAR(covered_share(120, 0.6f), 0.6, 0.02);
  EXPECT_NEAR(covered_share(40, 0.5f), 0.5, 0.03);
}

// Strands run along v: walking along v stays on a strand far longer than walking across u.
TEST(Strands, RunAlongV) {
  int changes_along_v = 0, changes_across_u = 0;
  bool last_v = strand_at(0.3f, 0.0f, 120, 0.5f).covered;
  bool last_u = strand_at(0.0f, 0.3f, 120, 0.5f).covered;
  for (int i = 1; i <= 2000; ++i) {
    const float t = i * 0.0005f;
    const bool on_v = strand_at(0.3f, t, 120, 0.5f).covered;
    const bool on_u = strand_at(t, 0.3f, 120, 0.5f).covered;
    changes_along_v += on_v != last_v;
    changes_across_u += on_u != last_u;
    last_v = on_v;
    last_u = on_u;
  }
  // Across u: two edges per strand, 120 strands per unit over one unit.
  EXPECT_GT(changes_across_u, 150);
  EXPECT_LT(changes_along_v, changes_across_u / 5);
}

TEST(Strands, ShadesVaryAndStayInRange) {
  float lo = 10, hi = 0;
  for (int i = 0; i < 2000; ++i) {
    const StrandSample s = strand_at(i * 0.0011f, 0.5f, 120, 0.6f);
    if (!s.covered) {
      EXPECT_EQ(s.shade, 1.0f);
      continue;
    }
    lo = std::min(lo, s.shade);
    hi = std::max(hi, s.shade);
  }
  EXPECT_GE(lo, 0.5f);
  EXPECT_LE(hi, 1.15f);
  EXPECT_GT(hi - lo, 0.25f);  // neither one flat colour nor noise beyond the range
}

}  // namespace
}  // namespace wheelpose::render
