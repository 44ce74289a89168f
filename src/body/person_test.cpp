#include "body/person.h"

#include <gtest/gtest.h>

#include <map>
#include <set>

#include "body/test_data.h"
#include "core/error.h"

namespace wheelpose::body {
namespace {

using testing::body_data;

TEST(Person, SeatContactBelowOneCentimetreForEveryChairType) {
  for (WheelchairType type :
       {WheelchairType::kManual, WheelchairType::kSport, WheelchairType::kPower}) {
    for (std::uint64_t seed : {1u, 7u, 42u}) {
      PersonSpec spec = sample_spec(seed);
      spec.wheelchair = type;
      const Person person = build_person(body_data(), spec);
      std::string part;
      const float depth = max_penetration(person.chair, person.vertices, &part);
      EXPECT_LT(depth, 0.01f) << wheelchair_type_name(type) << " seed " << seed << " " << part;
      // Seated on the seat: the pelvis is above the cushion, the floor under the chair.
      float lowest = 1e9f;
      for (const auto& v : person.vertices) lowest = std::min(lowest, v.y());
      EXPECT_GT(lowest, 0.0f);
      // A real seat carries the buttocks (low, because the seated pose raises the thighs 35
      // degrees and so the feet), the feet are on the footplate.
      if (spec.params.age_years >= 18) {
        const double seat = person.chair.dimensions["seat_height"].get<double>();
        EXPECT_GT(seat, 0.2) << wheelchair_type_name(type) << " seed " << seed;
        EXPECT_LT(seat, 0.65) << wheelchair_type_name(type) << " seed " << seed;
      }
      const float pelvis_above_seat = static_cast<float>(person.joints[motion::kPelvis].y()) -
                                      (person.chair.dimensions["seat_height"].get<float>());
      EXPECT_GT(pelvis_above_seat, 0.03f);
      EXPECT_LT(pelvis_above_seat, 0.2f);
      // Seat depth from the thigh: most of it, ending before the calves (a bug once left
      // 6 cm seats because the buttocks counted as calves).
      const double thigh =
          (person.joints[motion::kLeftKnee] - person.joints[motion::kLeftHip]).norm();
      const double seat_depth = person.chair.dimensions["seat_depth"].get<double>();
      EXPECT_GT(seat_depth, 0.6 * thigh) << wheelchair_type_name(type) << " seed " << seed;
      EXPECT_LT(seat_depth, 0.95 * thigh) << wheelchair_type_name(type) << " seed " << seed;
    }
  }
}

TEST(Person, WithoutAWheelchairStandsOnTheFloor) {
  for (std::uint64_t seed : {1u, 7u, 42u}) {
    PersonSpec spec = sample_spec(seed);
    spec.wheelchair = WheelchairType::kNone;
    spec.proxies = {"clothes/shoes01"};
    // A seated clip's pose, turned 40 degrees: the legs straighten and turn with the pelvis.
    if (seed == 7) {
      motion::PoseRotations pose = rest_seated_pose();
      const Eigen::Quaterniond turn(Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitY()));
      for (auto& q : pose) q = turn * q;
      spec.pose = pose;
    }
    const Person standing = build_person(body_data(), spec);
    EXPECT_TRUE(standing.chair.parts.empty());
    EXPECT_TRUE(standing.chair.model.vertices.empty());
    EXPECT_EQ(standing.chair.dimensions["type"], "none");
    // The lowest point of body and shoes is on the floor; the ankles just above it.
    float lowest = 1e9f;
    for (const auto& v : standing.vertices) lowest = std::min(lowest, v.y());
    for (const auto& g : standing.garments)
      for (const auto& v : g.vertices) lowest = std::min(lowest, v.y());
    EXPECT_NEAR(lowest, 0.0f, 1e-5f) << "seed " << seed;
    for (int ankle : {15, 16}) {
      EXPECT_GT(standing.coco[ankle].y(), 0.02f);
      EXPECT_LT(standing.coco[ankle].y(), 0.2f);
      // Straight down from the knee.
      const Eigen::Vector3f shin = standing.coco[ankle - 2] - standing.coco[ankle];
      EXPECT_GT(shin.normalized().y(), 0.98f) << "seed " << seed;
    }
    // Straight legs: the hips are about a leg's length up, well above where they sit in a chair.
    spec.wheelchair = WheelchairType::kManual;
    const Person seated = build_person(body_data(), spec);
    const double stature = standing.description["stature_m"].get<double>();
    EXPECT_GT(standing.coco[11].y(), 0.4 * stature) << "seed " << seed;
    EXPECT_GT(standing.coco[11].y(), seated.coco[11].y() + 0.1f) << "seed " << seed;
    EXPECT_GT(standing.coco[0].y(), seated.coco[0].y() + 0.2f) << "seed " << seed;
  }
}

TEST(Person, ChairFittedToBody) {
  PersonSpec narrow = sample_spec(3), wide = sample_spec(3);
  narrow.params.weight = 0.0;
  wide.params.weight = 1.0;
  narrow.wheelchair = wide.wheelchair = WheelchairType::kManual;
  const Person a = build_person(body_data(), narrow), b = build_person(body_data(), wide);
  EXPECT_GT(b.chair.dimensions["seat_width"].get<double>(),
            a.chair.dimensions["seat_width"].get<double>() + 0.03);
}

TEST(Person, SportChairHasCamberAndNoArmrestsPowerHasBase) {
  PersonSpec spec = sample_spec(5);
  spec.wheelchair = WheelchairType::kSport;
  const Person sport = build_person(body_data(), spec);
  EXPECT_GE(sport.chair.dimensions["camber_deg"].get<double>(), 12.0);
  for (const auto& p : sport.chair.parts) EXPECT_EQ(p.part.find("armrest"), std::string::npos);
  spec.wheelchair = WheelchairType::kPower;
  const Person power = build_person(body_data(), spec);
  std::set<std::string> parts;
  for (const auto& p : power.chair.parts) parts.insert(p.part);
  for (const char* need : {"base", "battery", "motor_l", "joystick", "headrest"}) {
    EXPECT_TRUE(parts.count(need)) << need;
  }
}

TEST(Person, KeypointsOnTheHead) {
  const Person p = build_person(body_data(), sample_spec(11));
  const Eigen::Vector3f nose = p.coco[0], eye_l = p.coco[1], eye_r = p.coco[2], ear_l = p.coco[3],
                        ear_r = p.coco[4];
  EXPECT_GT(eye_l.x(), eye_r.x());  // subject's left is +X
  EXPECT_GT(ear_l.x(), eye_l.x());
  EXPECT_LT(ear_r.x(), eye_r.x());
  EXPECT_GT(nose.z(), ear_l.z() + 0.05f);  // facing +Z
  EXPECT_NEAR((eye_l - eye_r).norm(), 0.062f, 0.02f);
}

// Where COCO's annotators put the points: hips 9 cm and shoulders 4 cm up the torso, ears at
// the ear's centre (inside the outermost rim vertex, lower, a little forward), the rest as is.
TEST(Person, AnnotatedKeypointsSitWhereCocoPutsThem) {
  const Person p = build_person(body_data(), sample_spec(11));
  const Eigen::Vector3f up =
      (p.joints[motion::kNeckBase] - p.joints[motion::kPelvis]).cast<float>().normalized();
  for (int k : {11, 12}) EXPECT_LT((p.annotated[k] - p.coco[k] - 0.09f * up).norm(), 1e-5f) << k;
  for (int k : {5, 6}) EXPECT_LT((p.annotated[k] - p.coco[k] - 0.04f * up).norm(), 1e-5f) << k;
  for (int k : {0, 1, 2, 7, 8, 9, 10, 13, 14, 15, 16}) EXPECT_EQ(p.annotated[k], p.coco[k]) << k;
  // Ears: 0.5-2.5 cm from the rim vertex, nearer the midline, lower, still outside the eyes.
  for (int side : {0, 1}) {
    const Eigen::Vector3f rim = p.coco[3 + side], centre = p.annotated[3 + side];
    EXPECT_GT((centre - rim).norm(), 0.005f) << side;
    EXPECT_LT((centre - rim).norm(), 0.025f) << side;
    EXPECT_LT(std::abs(centre.x()), std::abs(rim.x())) << side;
    EXPECT_LT(centre.dot(up), rim.dot(up)) << side;
    EXPECT_GT(std::abs(centre.x()), std::abs(p.coco[1 + side].x())) << side;
  }
  // The left and right ears mirror each other on the symmetric base mesh.
  const BodyData& data = body_data();
  EXPECT_EQ(data.ear_centres()[0].size(), data.ear_centres()[1].size());
  EXPECT_GE(data.ear_centres()[0].size(), 20u);
}

TEST(Person, DeterministicPerSeed) {
  EXPECT_EQ(sample_spec(9).params.to_json(), sample_spec(9).params.to_json());
  EXPECT_NE(sample_spec(9).params.to_json(), sample_spec(10).params.to_json());
  const Person a = build_person(body_data(), sample_spec(9));
  const Person b = build_person(body_data(), sample_spec(9));
  EXPECT_EQ(a.description.dump(), b.description.dump());
}

TEST(Person, OverridesApplyAndRejectGarbage) {
  PersonSpec spec = sample_spec(1);
  apply_overrides(spec, {"age=80", "wheelchair=power"});
  EXPECT_DOUBLE_EQ(spec.params.age_years, 80);
  EXPECT_EQ(spec.wheelchair, WheelchairType::kPower);
  EXPECT_THROW(apply_overrides(spec, {"wheelchair=rocket"}), Error);
  EXPECT_THROW(apply_overrides(spec, {"age"}), Error);
}

}  // namespace
}  // namespace wheelpose::body

namespace wheelpose::body {
namespace {

std::size_t open_edges(const std::vector<std::array<unsigned, 3>>& tris) {
  std::map<std::pair<unsigned, unsigned>, int> count;
  for (const auto& t : tris) {
    for (int k = 0; k < 3; ++k) {
      count[{std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])}]++;
    }
  }
  std::size_t open = 0;
  for (const auto& [edge, n] : count) open += n == 1;
  return open;
}

TEST(LimbDifference, CutsCapsAndMarksJointsAbsent) {
  PersonSpec whole = sample_spec(21);
  whole.limbs = {};
  const Person full = build_person(testing::body_data(), whole);
  for (const char* cut : {"left_leg=below_knee", "left_leg=above_knee", "right_arm=below_elbow",
                          "right_arm=above_elbow"}) {
    PersonSpec spec = whole;
    apply_overrides(spec, {cut});
    const Person p = build_person(testing::body_data(), spec);
    EXPECT_LT(p.vertices.size(), full.vertices.size() - 200) << cut;
    // Caps close every opening: no more open edges than the uncut body has.
    EXPECT_EQ(open_edges(p.triangles), open_edges(full.triangles)) << cut;
    const bool leg = std::string(cut).find("leg") != std::string::npos;
    const bool above = std::string(cut).find("above") != std::string::npos;
    const int far_kp = leg ? 15 : 10;  // left_ankle / right_wrist
    const int mid_kp = leg ? 13 : 8;   // left_knee / right_elbow
    EXPECT_FALSE(p.coco_present[far_kp]) << cut;
    EXPECT_EQ(p.coco_present[mid_kp], !above) << cut;
    // Hardly anything is left where the removed hand or foot was (the hand lies near a thigh).
    auto near = [&](const Person& q) {
      int n = 0;
      for (const auto& v : q.vertices) n += (v - p.coco[far_kp]).norm() < 0.05f;
      return n;
    };
    EXPECT_LT(near(p) * 5, near(full)) << cut;
    EXPECT_LT(max_penetration(p.chair, p.vertices), 0.01f) << cut;
  }
  PersonSpec bad = whole;
  EXPECT_THROW(apply_overrides(bad, {"left_leg=below_elbow"}), Error);
  EXPECT_THROW(apply_overrides(bad, {"tail_arm=none"}), Error);
}

}  // namespace
}  // namespace wheelpose::body

namespace wheelpose::body {
namespace {

// The CC-BY model carries the person: its seat surface at the fitted seat height, on the floor.
TEST(Person, CcByChairIsScaledUnderTheSeat) {
  PersonSpec spec = sample_spec(5);
  spec.wheelchair = WheelchairType::kCcBy;
  const Person p = build_person(testing::body_data(), spec);
  ASSERT_FALSE(p.chair.model.vertices.empty());
  EXPECT_TRUE(p.chair.parts.empty());
  float lowest = 1e9f;
  for (const auto& v : p.chair.model.vertices) lowest = std::min(lowest, v.y());
  EXPECT_NEAR(lowest, 0.0f, 1e-4f);
  EXPECT_NEAR(seat_surface_height(p.chair.model), p.chair.dimensions["seat_height"].get<float>(),
              0.012f);
  const float scale = p.chair.dimensions["scale"].get<float>();
  EXPECT_GT(scale, 0.6f);
  EXPECT_LT(scale, 1.6f);
  EXPECT_EQ(wheelchair_type_from_name("cc_by"), WheelchairType::kCcBy);
}

}  // namespace
}  // namespace wheelpose::body
