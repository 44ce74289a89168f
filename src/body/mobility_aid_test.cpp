// Mobility aids: held at the posed hands, resting on the floor, one per hand present.

#include "body/mobility_aid.h"

#include <gtest/gtest.h>

#include "body/person.h"
#include "body/test_data.h"
#include "core/error.h"

namespace wheelpose::body {
namespace {

using testing::body_data;

Person with_aid(MobilityAidType type, LimbCuts limbs = {}) {
  PersonSpec spec = sample_spec(12);
  spec.mobility_aid = type;
  spec.limbs = limbs;
  return build_person(body_data(), spec);
}

// The lowest and highest point of every primitive's end caps (tubes run along local x).
std::pair<float, float> y_range(const Primitive& p) {
  const Eigen::Vector3f a = p.centre - p.half.x() * p.axes.col(0);
  const Eigen::Vector3f b = p.centre + p.half.x() * p.axes.col(0);
  return {std::min(a.y(), b.y()), std::max(a.y(), b.y())};
}

int count_parts(const MobilityAid& aid, const std::string& prefix) {
  int n = 0;
  for (const auto& p : aid.parts) n += p.part.rfind(prefix, 0) == 0;
  return n;
}

TEST(MobilityAid, CaneIsHeldInTheRightHandAndReachesDown) {
  const Person p = with_aid(MobilityAidType::kCane);
  ASSERT_EQ(p.aid.type, MobilityAidType::kCane);
  const Primitive* shaft = nullptr;
  for (const auto& part : p.aid.parts)
    if (part.part == "cane_shaft_right") shaft = &part;
  ASSERT_NE(shaft, nullptr);
  const Eigen::Vector3f top = shaft->centre + shaft->half.x() * shaft->axes.col(0);
  const Eigen::Vector3f bottom = shaft->centre - shaft->half.x() * shaft->axes.col(0);
  const Eigen::Vector3f grip = top.y() > bottom.y() ? top : bottom;
  EXPECT_LT((grip - p.coco[10]).norm(), 0.1f);  // right wrist
  for (const auto& part : p.aid.parts) EXPECT_GE(y_range(part).first, -0.02f) << part.part;
  EXPECT_LT(std::min(top.y(), bottom.y()), grip.y() - 0.3f);
}

TEST(MobilityAid, CrutchesOnePerHandPresent) {
  EXPECT_EQ(count_parts(with_aid(MobilityAidType::kCrutches).aid, "crutch_cuff"), 2);
  LimbCuts no_left_hand{};
  no_left_hand[static_cast<int>(Limb::kLeftArm)] = Cut::kBelow;
  const Person one = with_aid(MobilityAidType::kCrutches, no_left_hand);
  EXPECT_EQ(count_parts(one.aid, "crutch_cuff_left"), 0);
  EXPECT_EQ(count_parts(one.aid, "crutch_cuff_right"), 1);
  LimbCuts no_hands{};
  no_hands[static_cast<int>(Limb::kLeftArm)] = Cut::kAbove;
  no_hands[static_cast<int>(Limb::kRightArm)] = Cut::kBelow;
  const Person none = with_aid(MobilityAidType::kCane, no_hands);
  EXPECT_EQ(none.aid.type, MobilityAidType::kNone);
  EXPECT_TRUE(none.aid.parts.empty());
}

TEST(MobilityAid, WalkerStandsOnTheFloorInFrontOfTheKnees) {
  const Person p = with_aid(MobilityAidType::kWalker);
  ASSERT_EQ(count_parts(p.aid, "walker_leg"), 4);
  const float knees_z = std::max(p.coco[13].z(), p.coco[14].z());
  for (const auto& part : p.aid.parts) {
    if (part.part.rfind("walker_leg", 0) != 0) continue;
    EXPECT_NEAR(y_range(part).first, 0.0f, 1e-4f);
    EXPECT_GT(part.centre.z(), knees_z);
  }
  // Nothing of the walker inside the body's knees region: its legs clear the shins.
  Wheelchair walker;
  walker.parts = p.aid.parts;
  EXPECT_LT(max_penetration(walker, p.vertices), 0.01f);
}

TEST(MobilityAid, NamesRoundTripAndGarbageIsRejected) {
  for (auto t : {MobilityAidType::kNone, MobilityAidType::kCane, MobilityAidType::kCrutches,
                 MobilityAidType::kWalker})
    EXPECT_EQ(mobility_aid_from_name(mobility_aid_name(t)), t);
  EXPECT_THROW(mobility_aid_from_name("skis"), Error);
}

}  // namespace
}  // namespace wheelpose::body
