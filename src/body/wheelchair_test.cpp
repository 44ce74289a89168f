#include "body/wheelchair.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/error.h"

namespace wheelpose::body {
namespace {

bool has_part(const Wheelchair& chair, const std::string& prefix) {
  for (const Primitive& p : chair.parts)
    if (p.part.rfind(prefix, 0) == 0) return true;
  return false;
}

Wheelchair chair_of(WheelchairType type, std::uint64_t seed, const SeatFit& fit = {}) {
  RandomStream stream(seed, {"test", "wheelchair"});
  return make_wheelchair(type, fit, stream);
}

TEST(Wheelchair, SeatIsFittedToTheBody) {
  SeatFit fit;
  fit.hip_width = 0.40f;
  fit.seat_top = 0.05f;
  fit.back_z = -0.2f;
  fit.thigh_length = 0.45f;
  fit.seat_front_limit = 0.35f;
  fit.feet_bottom = -0.45f;
  for (WheelchairType type :
       {WheelchairType::kManual, WheelchairType::kSport, WheelchairType::kPower}) {
    for (std::uint64_t seed = 0; seed < 20; ++seed) {
      const Wheelchair c = chair_of(type, seed, fit);
      const auto& d = c.dimensions;
      // Width: the hips plus 2-6 cm; depth: 80-92 % of the thigh, ending before the calves.
      EXPECT_GE(d["seat_width"].get<float>(), fit.hip_width + 0.02f - 1e-6f);
      EXPECT_LE(d["seat_width"].get<float>(), fit.hip_width + 0.06f + 1e-6f);
      EXPECT_LE(d["seat_depth"].get<float>(), fit.seat_front_limit - (fit.back_z - 0.003f) + 1e-6f);
      EXPECT_LE(d["seat_depth"].get<float>(), fit.thigh_length * 0.92f + 1e-6f);
      // The footplate carries the feet, 4-8 cm (plus its 2 cm) above the floor.
      const float plate_top = fit.feet_bottom - 0.003f;
      EXPECT_NEAR(d["footplate_height"].get<float>(), plate_top - c.ground_y, 1e-6f);
      EXPECT_GE(plate_top - c.ground_y, 0.06f - 1e-5f);
      EXPECT_LE(plate_top - c.ground_y, 0.10f + 1e-5f);
      EXPECT_EQ(c.colours.size(), 4u);
      // No part sinks below the floor.
      for (const Primitive& p : c.parts) {
        const Eigen::Vector3f extent = p.axes.cwiseAbs() * p.half;
        EXPECT_GE(p.centre.y() - extent.y(), c.ground_y - 0.005f) << p.part;
      }
    }
  }
}

TEST(Wheelchair, EachTypeHasItsParts) {
  const Wheelchair manual = chair_of(WheelchairType::kManual, 3);
  const Wheelchair sport = chair_of(WheelchairType::kSport, 3);
  const Wheelchair power = chair_of(WheelchairType::kPower, 3);
  EXPECT_TRUE(has_part(manual, "armrest") && has_part(manual, "caster"));
  EXPECT_TRUE(manual.dimensions.contains("rear_wheel_radius"));
  EXPECT_EQ(manual.dimensions["camber_deg"].get<float>(), 0.0f);
  // Sport: cambered wheels (12-18°), no armrests.
  EXPECT_FALSE(has_part(sport, "armrest"));
  EXPECT_GE(sport.dimensions["camber_deg"].get<float>(), 12.0f - 1e-4f);
  EXPECT_LE(sport.dimensions["camber_deg"].get<float>(), 18.0f + 1e-4f);
  EXPECT_FALSE(sport.dimensions.contains("armrest_height"));
  // Power: base, battery, drive wheels, headrest and joystick; no push wheels.
  for (const char* part : {"base", "battery", "drive_wheel", "headrest", "joystick"})
    EXPECT_TRUE(has_part(power, part)) << part;
  EXPECT_FALSE(power.dimensions.contains("rear_wheel_radius"));
  EXPECT_TRUE(power.dimensions.contains("drive_wheel_radius"));
  const Wheelchair none = chair_of(WheelchairType::kNone, 3);
  EXPECT_TRUE(none.parts.empty());
  EXPECT_EQ(none.dimensions["type"], "none");
}

TEST(Wheelchair, PowerChairsWithoutAHeadrestHaveAFoldingChairsBack) {
  for (std::uint64_t seed = 0; seed < 20; ++seed) {
    const Wheelchair rehab = chair_of(WheelchairType::kPower, seed);
    RandomStream stream(seed, {"test", "wheelchair"});
    const Wheelchair folding =
        make_wheelchair(WheelchairType::kPower, SeatFit{}, stream, {.headrest = false});
    EXPECT_TRUE(has_part(rehab, "headrest"));
    EXPECT_FALSE(has_part(folding, "headrest"));
    const float tall = rehab.dimensions["backrest_height"].get<float>();
    const float low = folding.dimensions["backrest_height"].get<float>();
    EXPECT_GE(tall, 0.50f);
    EXPECT_LE(tall, 0.60f);
    EXPECT_GE(low, 0.40f);
    EXPECT_LE(low, 0.50f);
    EXPECT_FLOAT_EQ(low + 0.10f, tall);  // the same draw, so every other dimension stays too
    EXPECT_EQ(folding.dimensions["seat_width"], rehab.dimensions["seat_width"]);
    EXPECT_EQ(folding.dimensions["headrest"], false);
    EXPECT_FALSE(rehab.dimensions.contains("headrest"));
    // Other types have no headrest to leave out.
    RandomStream manual_stream(seed, {"test", "wheelchair"});
    EXPECT_EQ(
        make_wheelchair(WheelchairType::kManual, SeatFit{}, manual_stream, {.headrest = false})
            .dimensions,
        chair_of(WheelchairType::kManual, seed).dimensions);
  }
}

TEST(Wheelchair, SameStreamSameChairOtherSeedOtherChair) {
  const Wheelchair a = chair_of(WheelchairType::kManual, 7);
  const Wheelchair b = chair_of(WheelchairType::kManual, 7);
  const Wheelchair c = chair_of(WheelchairType::kManual, 8);
  EXPECT_EQ(a.dimensions.dump(), b.dimensions.dump());
  ASSERT_EQ(a.parts.size(), b.parts.size());
  for (std::size_t i = 0; i < a.parts.size(); ++i) EXPECT_EQ(a.parts[i].centre, b.parts[i].centre);
  EXPECT_NE(a.dimensions.dump(), c.dimensions.dump());
}

TEST(Wheelchair, MaxPenetrationIsTheDeepestPointAndNamesThePart) {
  Primitive box;
  box.part = "seat";
  box.half = Eigen::Vector3f(0.5f, 0.2f, 0.1f);
  box.centre = Eigen::Vector3f(1, 0, 0);
  Wheelchair chair;
  chair.parts = {box};
  std::string part;
  EXPECT_NEAR(
      max_penetration(chair, {Eigen::Vector3f(3, 0, 0), Eigen::Vector3f(1, 0, 0.08f)}, &part),
      0.02f, 1e-6f);
  EXPECT_EQ(part, "seat");
}

TEST(Wheelchair, InsideDepthHandComputed) {
  Primitive box;
  box.half = {1, 2, 3};
  EXPECT_FLOAT_EQ(inside_depth(box, {0.5f, 0, 0}), 0.5f);
  EXPECT_LT(inside_depth(box, {1.5f, 0, 0}), 0);
  Primitive cyl;
  cyl.kind = Primitive::kCylinder;
  cyl.half = {0.1f, 0.3f, 0.3f};
  EXPECT_FLOAT_EQ(inside_depth(cyl, {0, 0.25f, 0}), 0.05f);
  EXPECT_LT(inside_depth(cyl, {0, 0.2f, 0.25f}), 0);
}

TEST(Wheelchair, EmptyChairStandsOnTheFloor) {
  RandomStream s(4, {"empty"});
  const Wheelchair c = make_empty_wheelchair(WheelchairType::kManual, s);
  const TriMesh m = primitive_mesh(c, 2);
  float lowest = 1e9f;
  for (const auto& v : m.vertices) lowest = std::min(lowest, v.y());
  EXPECT_NEAR(lowest, c.ground_y, 3e-3f);  // polygonal tyre ring
}

TEST(Wheelchair, ThinTubesGetFewerSidesAndStayRound) {
  EXPECT_EQ(cylinder_segments(0.004f), 6);  // a spoke
  EXPECT_EQ(cylinder_segments(0.011f), 14);
  EXPECT_EQ(cylinder_segments(0.05f), 24);
  for (const float radius : {0.004f, 0.05f}) {
    const Primitive spoke = make_tube("spoke", {0, 0, 0}, {0, 0.3f, 0}, radius, 3);
    const TriMesh m = primitive_mesh(std::vector<Primitive>{spoke}, spoke.material);
    // Per side: a quad (2 triangles) and a triangle in each end cap.
    EXPECT_EQ(m.triangles.size(), 4u * cylinder_segments(radius)) << radius;
    for (const auto& v : m.vertices) {
      const float from_axis = std::hypot(v.x(), v.z());
      EXPECT_TRUE(from_axis < 1e-6f || std::abs(from_axis - radius) < 1e-6f) << from_axis;
    }
  }
}

TEST(Wheelchair, CcByModelLoadsAtItsSize) {
  const TriMesh m = load_cc_by_wheelchair();
  Eigen::Vector3f lo = m.vertices[0], hi = m.vertices[0];
  for (const auto& v : m.vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  EXPECT_NEAR(hi.x() - lo.x(), 0.64f, 0.01f);
  EXPECT_NEAR(hi.y() - lo.y(), 0.91f, 0.01f);
  EXPECT_NEAR(hi.z() - lo.z(), 0.77f, 0.01f);
}

TEST(Wheelchair, TypeNamesRoundTripAndUnknownIsAnError) {
  for (WheelchairType type :
       {WheelchairType::kManual, WheelchairType::kSport, WheelchairType::kPower,
        WheelchairType::kCcBy, WheelchairType::kNone}) {
    EXPECT_EQ(wheelchair_type_from_name(wheelchair_type_name(type)), type);
  }
  EXPECT_THROW(wheelchair_type_from_name("rocket"), Error);
}

}  // namespace
}  // namespace wheelpose::body
