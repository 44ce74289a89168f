#include "body/placed_person.h"

#include <gtest/gtest.h>

#include <map>

#include "body/test_data.h"

namespace wheelpose::body {
namespace {

using Eigen::Vector3f;
using testing::body_data;

const PlacedPart* find_part(const std::vector<PlacedPart>& parts, const std::string& name) {
  for (const PlacedPart& p : parts) {
    if (p.name == name) return &p;
  }
  return nullptr;
}

std::size_t body_triangles(const std::vector<PlacedPart>& parts) {
  std::size_t n = 0;
  for (const PlacedPart& p : parts) {
    if (p.name == "skin" || p.name == "top" || p.name == "bottom" || p.name == "shoes" ||
        p.name == "lips") {
      n += p.triangles.size();
    }
  }
  return n;
}

Eigen::Affine3f placement() {
  return Eigen::Affine3f(Eigen::Translation3f(1.0f, 0.0f, -4.0f) *
                         Eigen::AngleAxisf(0.6f, Vector3f::UnitY()) * Eigen::Scaling(1.1f));
}

// The lips are a small region of the face, around the mouth: below the nose, above the chin,
// in front of the ears, a few hundred triangles, as wide as a mouth.
TEST(PlacedPerson, LipsAreTheirOwnPartAroundTheMouth) {
  PersonSpec spec = sample_spec(11);
  spec.wheelchair = WheelchairType::kNone;
  const Person person = build_person(body_data(), spec);
  const std::vector<PlacedPart> parts =
      place_person(person, body_data().rig(), {}, Eigen::Affine3f::Identity());
  const PlacedPart* lips = find_part(parts, "lips");
  ASSERT_NE(lips, nullptr);
  EXPECT_EQ(lips->paint, Paint::kLips);
  EXPECT_EQ(lips->colour, person.skin);
  EXPECT_GT(lips->triangles.size(), 100u);
  EXPECT_LT(lips->triangles.size(), 1500u);
  Eigen::AlignedBox3f box;
  for (const Vector3f& p : lips->positions) box.extend(p);
  const Vector3f nose = person.coco[0];
  const Vector3f ear_mid = 0.5f * (person.coco[3] + person.coco[4]);
  const Vector3f forward = (nose - ear_mid).normalized();
  EXPECT_LT(box.max().y(), nose.y());                       // below the nose tip
  EXPECT_GT(box.min().y(), nose.y() - 0.09f);               // above the chin
  EXPECT_GT((box.center() - ear_mid).dot(forward), 0.06f);  // at the front of the face
  const float width = box.sizes().maxCoeff();
  EXPECT_GT(width, 0.03f);
  EXPECT_LT(width, 0.09f);
}

TEST(PlacedPerson, BodyRegionsSplitTheBodyAndAreCarriedIntoTheWorld) {
  PersonSpec spec = sample_spec(7);
  spec.wheelchair = WheelchairType::kManual;
  spec.mobility_aid = MobilityAidType::kCane;
  spec.proxies = {"hair/short02", "clothes/shoes01"};
  const Person person = build_person(body_data(), spec);
  const Eigen::Affine3f to_world = placement();
  const std::vector<PlacedPart> parts = place_person(person, body_data().rig(), {}, to_world);

  // Every body triangle is in exactly one region; regions come first, in a fixed order.
  EXPECT_EQ(body_triangles(parts), person.triangles.size());
  ASSERT_GE(parts.size(), 4u);
  EXPECT_EQ(parts[0].name, "skin");
  EXPECT_EQ(parts[0].paint, Paint::kSkin);
  EXPECT_EQ(parts[0].colour, person.skin);
  // Long sleeves and trousers show; worn shoes hide the feet, so no foot region is left.
  for (const char* region : {"top", "bottom"}) {
    ASSERT_NE(find_part(parts, region), nullptr) << region;
    EXPECT_EQ(find_part(parts, region)->owner, PartOwner::kBody);
  }
  EXPECT_EQ(find_part(parts, "shoes"), nullptr);
  for (const PlacedPart& p : parts) {
    ASSERT_EQ(p.normals.size(), p.positions.size()) << p.name;
    for (const Vector3f& n : p.normals) ASSERT_NEAR(n.norm(), 1.0f, 1e-4f) << p.name;
    for (const Eigen::Vector3i& t : p.triangles) {
      for (int c = 0; c < 3; ++c) {
        ASSERT_GE(t[c], 0);
        ASSERT_LT(t[c], static_cast<int>(p.positions.size())) << p.name;
      }
    }
  }
  // The garments worn, in the outfit's colours for them.
  ASSERT_NE(find_part(parts, "short02"), nullptr);
  EXPECT_EQ(find_part(parts, "short02")->paint, Paint::kHair);
  ASSERT_NE(find_part(parts, "shoes01"), nullptr);
  EXPECT_EQ(find_part(parts, "shoes01")->paint, Paint::kShoes);
  // The chair and the cane, in their own colours, placed like the body.
  const PlacedPart* frame = find_part(parts, "wheelchair_frame");
  ASSERT_NE(frame, nullptr);
  EXPECT_EQ(frame->owner, PartOwner::kWheelchair);
  EXPECT_EQ(frame->paint, Paint::kOwnColour);
  EXPECT_EQ(frame->colour, person.chair.colours[0]);
  const TriMesh chair_frame = primitive_mesh(person.chair, 0);
  ASSERT_EQ(frame->positions.size(), chair_frame.vertices.size());
  for (std::size_t v = 0; v < chair_frame.vertices.size(); v += 97) {
    EXPECT_LT((frame->positions[v] - to_world * chair_frame.vertices[v]).norm(), 1e-5f);
  }
  const PlacedPart* cane = find_part(parts, "mobility_aid_frame");
  ASSERT_NE(cane, nullptr);
  EXPECT_EQ(cane->owner, PartOwner::kMobilityAid);
  EXPECT_EQ(cane->colour, person.aid.colours[0]);
}

TEST(PlacedPerson, SleevesTrousersAndSuitsDecideWhatShowsSkin) {
  PersonSpec spec = sample_spec(3);
  spec.proxies = {};
  const Person person = build_person(body_data(), spec);
  auto triangles_of = [&](const DressCode& dress, const char* region) {
    const std::vector<PlacedPart> parts =
        place_person(person, body_data().rig(), dress, Eigen::Affine3f::Identity());
    const PlacedPart* p = find_part(parts, region);
    return p == nullptr ? std::size_t{0} : p->triangles.size();
  };
  const DressCode covered{true, true}, bare{false, false};
  // Short sleeves and trousers move forearms and calves from the outfit to the skin.
  EXPECT_GT(triangles_of(bare, "skin"), triangles_of(covered, "skin"));
  EXPECT_LT(triangles_of(bare, "top"), triangles_of(covered, "top"));
  EXPECT_LT(triangles_of(bare, "bottom"), triangles_of(covered, "bottom"));
  EXPECT_EQ(triangles_of(bare, "shoes"), triangles_of(covered, "shoes"));

  // A worn suit covers the body: what shows of the body is skin; the suit is cut by nearest bone
  // into a top (the top colour) and a bottom (the bottom colour) that share all its triangles.
  spec.proxies = {"clothes/male_casualsuit01"};
  const Person suited = build_person(body_data(), spec);
  const std::vector<PlacedPart> parts =
      place_person(suited, body_data().rig(), covered, Eigen::Affine3f::Identity());
  EXPECT_EQ(find_part(parts, "top"), nullptr);
  EXPECT_EQ(find_part(parts, "bottom"), nullptr);
  ASSERT_NE(find_part(parts, "skin"), nullptr);
  ASSERT_NE(find_part(parts, "lips"), nullptr);  // a suit leaves the lips their own
  EXPECT_EQ(find_part(parts, "skin")->triangles.size() + find_part(parts, "lips")->triangles.size(),
            suited.triangles.size());
  EXPECT_EQ(find_part(parts, "male_casualsuit01"), nullptr);
  const PlacedPart* top = find_part(parts, "male_casualsuit01_top");
  const PlacedPart* bottom = find_part(parts, "male_casualsuit01_bottom");
  ASSERT_NE(top, nullptr);
  ASSERT_NE(bottom, nullptr);
  EXPECT_EQ(top->paint, Paint::kTop);
  EXPECT_EQ(bottom->paint, Paint::kBottom);
  const auto suit =
      std::find_if(suited.garments.begin(), suited.garments.end(),
                   [](const Garment& g) { return g.name == "clothes/male_casualsuit01"; });
  ASSERT_NE(suit, suited.garments.end());
  EXPECT_EQ(top->triangles.size() + bottom->triangles.size(), suit->triangles.size());
  // The trousers hang below the shirt (the highest point of each, seated or not).
  const auto highest = [](const PlacedPart& p) {
    float y = -INFINITY;
    for (const auto& v : p.positions) y = std::max(y, v.y());
    return y;
  };
  EXPECT_LT(highest(*bottom), highest(*top) - 0.2f);
}

TEST(PlacedPerson, AnEmptyWheelchairHasItsPartsAndNoBody) {
  RandomStream stream(11, {"empty_wheelchair"});
  const Wheelchair chair = make_empty_wheelchair(WheelchairType::kManual, stream);
  const std::vector<PlacedPart> parts = place_wheelchair(chair, placement());
  ASSERT_FALSE(parts.empty());
  EXPECT_EQ(parts[0].name, "frame");
  for (const PlacedPart& p : parts) {
    EXPECT_EQ(p.owner, PartOwner::kWheelchair);
    EXPECT_EQ(p.paint, Paint::kOwnColour);
    EXPECT_TRUE(p.uvs.empty());
    EXPECT_FALSE(p.triangles.empty());
  }
}

}  // namespace
}  // namespace wheelpose::body
