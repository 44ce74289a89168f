// Hands on the push rims: the wrists meet the rim circles, the arm keeps its bone lengths.

#include "body/rim_reach.h"

#include <gtest/gtest.h>

#include "body/person.h"
#include "body/test_data.h"

namespace wheelpose::body {
namespace {

using testing::body_data;

float distance_to_circle(const Eigen::Vector3f& p, const Eigen::Vector3f& centre,
                         const Eigen::Vector3f& axis, float radius) {
  Eigen::Vector3f d = p - centre;
  const float along = d.dot(axis);
  const Eigen::Vector3f in_plane = d - along * axis;
  return std::hypot(in_plane.norm() - radius, along);
}

TEST(RimReach, WristsMeetTheRimsAndArmsKeepTheirLength) {
  for (WheelchairType type : {WheelchairType::kManual, WheelchairType::kSport}) {
    PersonSpec spec = sample_spec(8);
    spec.wheelchair = type;
    const Person free = build_person(body_data(), spec);
    spec.hands_on_rims = true;
    const Person pushing = build_person(body_data(), spec);
    for (bool left : {true, false}) {
      Eigen::Vector3f centre, axis;
      float radius = 0;
      ASSERT_TRUE(push_rim_circle(pushing.chair, left, centre, axis, radius));
      const int wrist = left ? 9 : 10, elbow = left ? 7 : 8, shoulder = left ? 5 : 6;
      // The wrist sits 4 cm outside the rim (the hand wraps it).
      EXPECT_LT(distance_to_circle(pushing.coco[wrist], centre, axis, radius), 0.06f)
          << wheelchair_type_name(type) << (left ? " left" : " right");
      EXPECT_GT(distance_to_circle(free.coco[wrist], centre, axis, radius), 0.06f);
      EXPECT_NEAR((pushing.coco[elbow] - pushing.coco[shoulder]).norm(),
                  (free.coco[elbow] - free.coco[shoulder]).norm(), 1e-3f);
      EXPECT_NEAR((pushing.coco[wrist] - pushing.coco[elbow]).norm(),
                  (free.coco[wrist] - free.coco[elbow]).norm(), 1e-3f);
    }
  }
}

TEST(RimReach, PowerChairsHaveNoRims) {
  PersonSpec spec = sample_spec(8);
  spec.wheelchair = WheelchairType::kPower;
  const Person plain = build_person(body_data(), spec);
  spec.hands_on_rims = true;
  const Person same = build_person(body_data(), spec);
  EXPECT_EQ(plain.vertices, same.vertices);
}

}  // namespace
}  // namespace wheelpose::body
