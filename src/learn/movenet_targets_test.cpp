#include "learn/movenet_targets.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>

namespace wheelpose::learn {
namespace {

// A 40×80 px person at (42, 40) in a 128 px input: grid 32, centre (62, 80) px = cell (20, 15)
// with offset (0, 0.5); keypoint 0 at (50.5, 45) px = (11.25, 12.625) cells.
TEST(MovenetTargets, GoldenValuesForOnePerson) {
  TrainPerson p;
  p.box = {42, 40, 40, 80};
  p.keypoints[0] = 50.5, p.keypoints[1] = 45, p.keypoints[2] = 2;
  p.keypoints[3 * 5] = 60, p.keypoints[3 * 5 + 1] = 70, p.keypoints[3 * 5 + 2] = 1;
  const MovenetTargets t = build_targets({p}, 128);
  ASSERT_EQ(t.grid, 32);
  ASSERT_EQ(t.centres.size(), 1u);
  const CentreTarget& c = t.centres[0];
  EXPECT_EQ(c.cell, 20 * 32 + 15);
  EXPECT_FLOAT_EQ(c.scale[0], 20);  // h in cells
  EXPECT_FLOAT_EQ(c.scale[1], 10);
  EXPECT_FLOAT_EQ(c.offset[0], 0);
  EXPECT_FLOAT_EQ(c.offset[1], 0.5);
  EXPECT_FLOAT_EQ(c.regress[0], 11.25 - 20);  // keypoint 0: dy, dx from the centre cell
  EXPECT_FLOAT_EQ(c.regress[1], 12.625 - 15);
  EXPECT_EQ(c.regress_mask[0], 1);
  EXPECT_EQ(c.regress_mask[1], 0);  // unlabelled
  EXPECT_EQ(c.regress_mask[5], 1);  // v = 1 trains too
  ASSERT_EQ(t.keypoints.size(), 2u);
  EXPECT_EQ(t.keypoints[0].cell, 11 * 32 + 12);
  EXPECT_FLOAT_EQ(t.keypoints[0].offset[0], 0.25);
  EXPECT_FLOAT_EQ(t.keypoints[0].offset[1], 0.625);
  // Peaks are exactly 1 where the focal loss counts positives, below 1 around them.
  EXPECT_EQ(t.centre_heatmap[20 * 32 + 15], 1.f);
  EXPECT_GT(t.centre_heatmap[20 * 32 + 16], 0.5f);
  EXPECT_LT(t.centre_heatmap[20 * 32 + 16], 1.f);
  EXPECT_EQ(t.keypoint_heatmap[(11 * 32 + 12) * 17 + 0], 1.f);
  EXPECT_EQ(t.keypoint_heatmap[(11 * 32 + 12) * 17 + 1], 0.f);  // other channel untouched
}

// With an offset radius every cell around a keypoint learns the offset to it, weighted by the
// person's Gaussian (σ = max(0.8, 0.1 · sqrt(20 · 10)) = √2 cells here); radius 0 is the
// one-cell rule.
TEST(MovenetTargets, OffsetsAroundAKeypointPointAtIt) {
  TrainPerson p;
  p.box = {42, 40, 40, 80};
  p.keypoints[0] = 50.5, p.keypoints[1] = 45, p.keypoints[2] = 2;  // (11.25, 12.625) cells
  const MovenetTargets one_cell = build_targets({p}, 128, 0);
  ASSERT_EQ(one_cell.keypoints.size(), 1u);
  EXPECT_EQ(one_cell.keypoints[0].weight, 1.f);
  const MovenetTargets t = build_targets({p}, 128, 1);
  ASSERT_EQ(t.keypoints.size(), 9u);
  for (const KeypointTarget& k : t.keypoints) {
    const int dy = k.cell / 32 - 11, dx = k.cell % 32 - 12;
    EXPECT_FLOAT_EQ(k.cell / 32 + k.offset[0], 11.25f);
    EXPECT_FLOAT_EQ(k.cell % 32 + k.offset[1], 12.625f);
    EXPECT_FLOAT_EQ(k.weight, std::exp(-(dy * dy + dx * dx) / 4.0f)) << dy << ", " << dx;
  }
  // Cut at the border: a keypoint in the corner cell has 4 cells within radius 1.
  p.keypoints[0] = 1, p.keypoints[1] = 1;
  EXPECT_EQ(build_targets({p}, 128, 1).keypoints.size(), 4u);
}

// Two people's same keypoint 3 cells apart: each cell between them points at the nearer one;
// their own cells keep weight 1.
TEST(MovenetTargets, ACellBetweenTwoKeypointsPointsAtTheNearer) {
  TrainPerson a;
  a.box = {0, 0, 40, 80};
  a.keypoints[0] = 40.5, a.keypoints[1] = 20.5, a.keypoints[2] = 2;  // cell (5, 10)
  TrainPerson b = a;
  b.box.x = 12;
  b.keypoints[0] = 52.5;  // cell (5, 13)
  const MovenetTargets t = build_targets({a, b}, 128, 2);
  std::map<int, const KeypointTarget*> row5;
  std::set<int> cells;
  for (const KeypointTarget& k : t.keypoints) {
    ASSERT_TRUE(cells.insert(k.cell).second) << "two targets in cell " << k.cell;
    if (k.cell / 32 == 5) row5[k.cell % 32] = &k;
  }
  ASSERT_EQ(row5.size(), 8u);  // x 8..15
  EXPECT_FLOAT_EQ(row5.at(10)->weight, 1.f);
  EXPECT_FLOAT_EQ(row5.at(13)->weight, 1.f);
  EXPECT_FLOAT_EQ(11 + row5.at(11)->offset[1], 10.125f);  // a's keypoint: 40.5 / 4
  EXPECT_FLOAT_EQ(12 + row5.at(12)->offset[1], 13.125f);  // b's: 52.5 / 4
  EXPECT_FLOAT_EQ(8 + row5.at(8)->offset[1], 10.125f);
  EXPECT_FLOAT_EQ(15 + row5.at(15)->offset[1], 13.125f);
}

// A crowd region gets no targets; its cells lose their heatmap weight except where a person's
// centre Gaussian reaches; a sample without one has no weight map at all.
TEST(MovenetTargets, ACrowdRegionIsIgnoredNotTaughtAsBackground) {
  TrainPerson person;
  person.box = {42, 40, 40, 80};  // centre cell (20, 15)
  person.keypoints[2] = 0;
  TrainPerson crowd;
  crowd.box = {0, 0, 64, 32};  // cells x 0..15, y 0..7
  crowd.ignore = true;
  crowd.keypoints[0] = 10, crowd.keypoints[1] = 10, crowd.keypoints[2] = 2;  // never a target
  EXPECT_TRUE(build_targets({person}, 128).heatmap_weight.empty());
  const MovenetTargets t = build_targets({person, crowd}, 128);
  ASSERT_EQ(t.centres.size(), 1u);
  EXPECT_TRUE(t.keypoints.empty());
  ASSERT_EQ(t.heatmap_weight.size(), 32u * 32u);
  EXPECT_EQ(t.heatmap_weight[0], 0.f);
  EXPECT_EQ(t.heatmap_weight[7 * 32 + 15], 0.f);   // the region's last cell
  EXPECT_EQ(t.heatmap_weight[8 * 32 + 15], 1.f);   // just below it
  EXPECT_EQ(t.heatmap_weight[7 * 32 + 16], 1.f);   // just right of it
  EXPECT_EQ(t.heatmap_weight[20 * 32 + 15], 1.f);  // the person
  EXPECT_EQ(t.centre_heatmap[0], 0.f);
  // Where the region overlaps the person's centre Gaussian, the person's cells keep their weight.
  crowd.box = {40, 60, 48, 40};
  const MovenetTargets overlap = build_targets({person, crowd}, 128);
  EXPECT_EQ(overlap.heatmap_weight[20 * 32 + 15], 1.f);
  EXPECT_EQ(overlap.heatmap_weight[15 * 32 + 21], 0.f);  // in the region, beyond the Gaussian
}

}  // namespace
}  // namespace wheelpose::learn
