#include "learn/movenet_targets.h"

#include <gtest/gtest.h>

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
