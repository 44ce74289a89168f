#include "learn/model_ensemble.h"

#include <gtest/gtest.h>

#include "core/error.h"

namespace wheelpose::learn {
namespace {

// A person whose 17 keypoints all sit at (kx, ky) with keypoint score `kscore`.
PosePrediction person(double x, double y, double w, double h, double score, double kx = 0,
                      double ky = 0, double kscore = 1) {
  PosePrediction p;
  p.bbox = {x, y, w, h};
  p.score = score;
  for (int k = 0; k < 17; ++k) {
    p.keypoints[3 * k] = kx;
    p.keypoints[3 * k + 1] = ky;
    p.keypoints[3 * k + 2] = kscore;
  }
  return p;
}

TEST(ModelEnsemble, APersonBothModelsFindIsAveraged) {
  // Scores 0.8 and 0.4: fused 0.6; box and keypoints weighted 2:1 toward the first.
  const auto out = fuse_models(
      {{person(0, 0, 30, 90, 0.8, 10, 20)}, {person(3, 0, 30, 90, 0.4, 40, 50, 0.5)}}, {});
  ASSERT_EQ(out.size(), 1u);
  EXPECT_DOUBLE_EQ(out[0].score, 0.6);
  EXPECT_DOUBLE_EQ(out[0].bbox.x, 1.0);
  EXPECT_DOUBLE_EQ(out[0].bbox.w, 30.0);
  // Keypoint weights 0.8 × 1 and 0.4 × 0.5: x = (0.8 × 10 + 0.2 × 40) / 1.0.
  EXPECT_DOUBLE_EQ(out[0].keypoints[0], 16.0);
  EXPECT_DOUBLE_EQ(out[0].keypoints[1], 26.0);
  EXPECT_DOUBLE_EQ(out[0].keypoints[2], 0.75);
}

TEST(ModelEnsemble, APersonOneModelAloneFindsKeepsItsShare) {
  // The second model's person has no partner: half its score, its own box and keypoints.
  const auto out = fuse_models(
      {{person(0, 0, 30, 90, 0.8)}, {person(0, 0, 30, 90, 0.6), person(200, 0, 30, 90, 0.9, 5, 6)}},
      {});
  ASSERT_EQ(out.size(), 2u);
  EXPECT_DOUBLE_EQ(out[0].score, 0.7);
  EXPECT_DOUBLE_EQ(out[1].score, 0.45);
  EXPECT_DOUBLE_EQ(out[1].bbox.x, 200.0);
  EXPECT_DOUBLE_EQ(out[1].keypoints[0], 5.0);
  EXPECT_DOUBLE_EQ(out[1].keypoints[2], 0.5);
}

TEST(ModelEnsemble, AGroupTakesOnePersonPerModel) {
  // Model 0 reports two overlapping boxes: they stay two people, each paired at most once.
  const auto out = fuse_models(
      {{person(0, 0, 30, 90, 0.9), person(2, 0, 30, 90, 0.5)}, {person(1, 0, 30, 90, 0.7)}}, {});
  ASSERT_EQ(out.size(), 2u);
  EXPECT_DOUBLE_EQ(out[0].score, 0.8);
  EXPECT_DOUBLE_EQ(out[1].score, 0.25);
}

TEST(ModelEnsemble, BoxesApartStayApartAndWeightsCount) {
  // IoU of the two boxes is 1/3, under 0.5: two people, scored by weights 0.25 and 0.75.
  const auto out = fuse_models({{person(0, 0, 20, 20, 0.8)}, {person(10, 0, 20, 20, 0.8)}},
                               {.iou = 0.5, .weights = {0.25, 0.75}});
  ASSERT_EQ(out.size(), 2u);
  EXPECT_DOUBLE_EQ(out[0].score, 0.6);
  EXPECT_DOUBLE_EQ(out[0].bbox.x, 10.0);
  EXPECT_DOUBLE_EQ(out[1].score, 0.2);
  // A lower IoU threshold joins them.
  EXPECT_EQ(fuse_models({{person(0, 0, 20, 20, 0.8)}, {person(10, 0, 20, 20, 0.8)}},
                        {.iou = 0.3, .weights = {}})
                .size(),
            1u);
}

TEST(ModelEnsemble, OneModelIsItselfAndWrongWeightsAreAnError) {
  const std::vector<PosePrediction> one = {person(0, 0, 10, 10, 0.3, 1, 2, 0.4),
                                           person(50, 0, 10, 10, 0.9, 3, 4, 0.6)};
  const auto out = fuse_models({one}, {});
  ASSERT_EQ(out.size(), 2u);
  EXPECT_DOUBLE_EQ(out[0].score, 0.9);
  EXPECT_DOUBLE_EQ(out[0].keypoints[0], 3.0);
  EXPECT_DOUBLE_EQ(out[0].keypoints[2], 0.6);
  EXPECT_DOUBLE_EQ(out[1].bbox.x, 0.0);
  EXPECT_THROW(fuse_models({one, one}, {.weights = {1.0}}), Error);
}

TEST(ModelEnsemble, AMirroredPersonComesBackWithSidesSwapped) {
  PosePrediction p = person(10, 5, 30, 90, 0.7);
  p.keypoints[3 * 1] = 12;  // left eye
  p.keypoints[3 * 1 + 2] = 0.9;
  p.keypoints[3 * 2] = 20;  // right eye
  p.keypoints[3 * 2 + 2] = 0.2;
  const std::vector<std::pair<int, int>> pairs = {{1, 2}};
  const PosePrediction m = mirror_prediction(p, 100, pairs);
  EXPECT_DOUBLE_EQ(m.bbox.x, 60.0);  // [10, 40) mirrors to [60, 90)
  EXPECT_DOUBLE_EQ(m.bbox.w, 30.0);
  EXPECT_DOUBLE_EQ(m.bbox.y, 5.0);
  EXPECT_DOUBLE_EQ(m.keypoints[3 * 1], 80.0);  // the right eye at 20 becomes the left at 80
  EXPECT_DOUBLE_EQ(m.keypoints[3 * 1 + 2], 0.2);
  EXPECT_DOUBLE_EQ(m.keypoints[3 * 2], 88.0);
  EXPECT_DOUBLE_EQ(m.keypoints[3 * 0], 100.0);  // the nose at x 0
  EXPECT_DOUBLE_EQ(m.score, 0.7);
  // Mirroring twice is the identity.
  const PosePrediction back = mirror_prediction(m, 100, pairs);
  for (std::size_t i = 0; i < p.keypoints.size(); ++i)
    EXPECT_DOUBLE_EQ(back.keypoints[i], p.keypoints[i]);
  EXPECT_DOUBLE_EQ(back.bbox.x, p.bbox.x);
}

}  // namespace
}  // namespace wheelpose::learn
