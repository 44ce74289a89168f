#include "learn/scale_merge.h"

#include <gtest/gtest.h>

namespace wheelpose::learn {
namespace {

PosePrediction person(double x, double y, double w, double h, double score) {
  PosePrediction p;
  p.bbox = {x, y, w, h};
  p.score = score;
  return p;
}

// Scale 0: input 256 of a 640-pixel image (0.4 input px per image px); scale 1: 640 (1.0).
std::vector<ScaleResult> two_scales(std::vector<PosePrediction> small_input,
                                    std::vector<PosePrediction> large_input) {
  return {{0.4, std::move(small_input)}, {1.0, std::move(large_input)}};
}

TEST(ScaleMerge, OneScaleKeepsEveryoneInScoreOrder) {
  const auto out =
      merge_scales({{1.0, {person(0, 0, 10, 10, 0.2), person(50, 0, 10, 10, 0.9)}}}, {});
  ASSERT_EQ(out.size(), 2u);
  EXPECT_DOUBLE_EQ(out[0].score, 0.9);
  EXPECT_DOUBLE_EQ(out[1].score, 0.2);
}

TEST(ScaleMerge, LargePeopleAreLeftToTheSmallerInput) {
  // A 400-pixel person is 400 px in the 640 input (over 192: dropped there) and 160 px in the
  // 256 input (kept); the 640 input's part-of-a-person box of 100 px stays, apart from it.
  const auto out =
      merge_scales(two_scales({person(100, 100, 200, 400, 0.6)},
                              {person(100, 100, 200, 400, 0.9), person(400, 0, 100, 100, 0.3)}),
                   {.max_person_px = 192});
  ASSERT_EQ(out.size(), 2u);
  EXPECT_DOUBLE_EQ(out[0].score, 0.6);
  EXPECT_DOUBLE_EQ(out[1].score, 0.3);
}

TEST(ScaleMerge, TheSmallestInputKeepsItsLargePeople) {
  // 1,000 px is 400 px even in the 256 input: still kept there, as no smaller input exists.
  const auto out = merge_scales(two_scales({person(0, 0, 500, 1000, 0.5)}, {}), {});
  ASSERT_EQ(out.size(), 1u);
}

TEST(ScaleMerge, OverlappingPeopleOfTwoInputsAreOnePerson) {
  // The same small person found at both inputs: the higher score stays.
  const auto out = merge_scales(
      two_scales({person(10, 10, 40, 100, 0.4)}, {person(12, 10, 40, 100, 0.7)}), {.iou = 0.5});
  ASSERT_EQ(out.size(), 1u);
  EXPECT_DOUBLE_EQ(out[0].score, 0.7);
  EXPECT_DOUBLE_EQ(out[0].bbox.x, 12);
}

TEST(ScaleMerge, EqualScoresKeepTheSmallerInputsPerson) {
  const auto out =
      merge_scales(two_scales({person(10, 10, 40, 100, 0.5)}, {person(12, 10, 40, 100, 0.5)}), {});
  ASSERT_EQ(out.size(), 1u);
  EXPECT_DOUBLE_EQ(out[0].bbox.x, 10);
}

TEST(ScaleMerge, ContainmentSuppressesPartsInsideAPerson) {
  const auto scales = two_scales({person(0, 0, 300, 500, 0.8)}, {person(50, 50, 60, 60, 0.3)});
  EXPECT_EQ(merge_scales(scales, {.max_person_px = 192}).size(), 2u);  // IoU alone: two
  EXPECT_EQ(merge_scales(scales, {.max_person_px = 192, .containment = 0.8}).size(), 1u);
}

TEST(ScaleMerge, SmallPeopleCanBeLeftToTheLargerInput) {
  // 20 px in the 256 input: under min_person_px 24, so only the 640 input's 50 px one counts.
  const auto out =
      merge_scales(two_scales({person(0, 0, 20, 50, 0.9)}, {person(300, 0, 20, 50, 0.2)}),
                   {.min_person_px = 24});
  ASSERT_EQ(out.size(), 1u);
  EXPECT_DOUBLE_EQ(out[0].score, 0.2);
}

}  // namespace
}  // namespace wheelpose::learn
