#include "render/strata.h"

#include <gtest/gtest.h>

#include <set>
#include <vector>

namespace wheelpose::render {
namespace {

constexpr int kB = ScreenStrata::kBlock;

// The cell of `point` on a grid of n × n cells of the unit square.
int cell(const std::array<float, 2>& point, int n) {
  return static_cast<int>(point[1] * n) * n + static_cast<int>(point[0] * n);
}

TEST(ScreenStrata, PointsLieInTheUnitSquare) {
  const ScreenStrata strata(7);
  for (int by = 0; by < 4; ++by) {
    for (int bx = 0; bx < 4; ++bx) {
      const ScreenStrata::Block block = strata.block(bx * kB, by * kB, bx + by);
      for (int pair = 0; pair < ScreenStrata::kPairs; ++pair) {
        for (int y = 0; y < kB; ++y) {
          for (int x = 0; x < kB; ++x) {
            const auto p = block.point(bx * kB + x, by * kB + y, pair);
            EXPECT_GE(p[0], 0.0f);
            EXPECT_LT(p[0], 1.0f);
            EXPECT_GE(p[1], 0.0f);
            EXPECT_LT(p[1], 1.0f);
          }
        }
      }
    }
  }
}

// Every aligned 2^k × 2^k square of pixels puts one point in each of the 4^k cells of side 2^−k:
// what makes the smoothing average stratified samples.
TEST(ScreenStrata, EveryAlignedSquareOfPixelsIsStratified) {
  const ScreenStrata strata(12345);
  for (int sample = 0; sample < 3; ++sample) {
    for (int b = 0; b < 6; ++b) {
      const int x0 = 37 * b * kB, y0 = 11 * b * kB;
      const ScreenStrata::Block block = strata.block(x0, y0, sample);
      for (int pair = 0; pair < ScreenStrata::kPairs; ++pair) {
        for (int side = 2; side <= kB; side *= 2) {
          for (int sy = 0; sy < kB; sy += side) {
            for (int sx = 0; sx < kB; sx += side) {
              std::set<int> cells;
              for (int y = sy; y < sy + side; ++y)
                for (int x = sx; x < sx + side; ++x)
                  cells.insert(cell(block.point(x0 + x, y0 + y, pair), side));
              EXPECT_EQ(static_cast<int>(cells.size()), side * side)
                  << "square of side " << side << " at " << sx << "," << sy << ", pair " << pair;
            }
          }
        }
      }
    }
  }
}

// Over many blocks, the point of any one pixel position is uniform: estimates stay unbiased.
TEST(ScreenStrata, EachPixelsPointIsUniformOverBlocks) {
  const ScreenStrata strata(99);
  constexpr int kBlocks = 4096, kBins = 8;
  for (int local : {0, 9, 63}) {
    std::vector<int> histogram(kBins * kBins, 0);
    double mean_u = 0, mean_v = 0;
    for (int b = 0; b < kBlocks; ++b) {
      const int x = (b % 64) * kB + local % kB, y = (b / 64) * kB + local / kB;
      const auto p = strata.block(x, y, 0).point(x, y, 1);
      ++histogram[cell(p, kBins)];
      mean_u += p[0];
      mean_v += p[1];
    }
    EXPECT_NEAR(mean_u / kBlocks, 0.5, 0.02);
    EXPECT_NEAR(mean_v / kBlocks, 0.5, 0.02);
    // 64 cells of expected count 64: a chi-square far above its 63 degrees of freedom would
    // mean some cells are favoured.
    double chi2 = 0;
    const double expected = static_cast<double>(kBlocks) / (kBins * kBins);
    for (int n : histogram) chi2 += (n - expected) * (n - expected) / expected;
    EXPECT_LT(chi2, 120.0) << "pixel " << local;
  }
}

// The order of pixels along the sequence is random per block (no pattern repeats every 8
// pixels), differs between pairs, and is a pure function of the seed.
TEST(ScreenStrata, OrderDiffersPerBlockAndPairAndFollowsTheSeed) {
  auto layout = [](const ScreenStrata& strata, int bx, int pair) {
    const ScreenStrata::Block block = strata.block(bx * kB, 0, 0);
    std::vector<int> cells;
    for (int y = 0; y < kB; ++y)
      for (int x = 0; x < kB; ++x) cells.push_back(cell(block.point(bx * kB + x, y, pair), kB));
    return cells;
  };
  const ScreenStrata a(5), same(5), other(6);
  EXPECT_EQ(layout(a, 0, 0), layout(same, 0, 0));
  EXPECT_NE(layout(a, 0, 0), layout(other, 0, 0));
  EXPECT_NE(layout(a, 0, 0), layout(a, 1, 0));
  EXPECT_NE(layout(a, 0, 0), layout(a, 0, 1));
}

}  // namespace
}  // namespace wheelpose::render
