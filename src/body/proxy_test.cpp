// MakeHuman proxies: parsed from the shared CC0 assets, fitted to posed bodies, hiding the skin
// they cover and dropping what hangs on a removed limb.

#include "body/proxy.h"

#include <gtest/gtest.h>

#include "body/person.h"
#include "body/test_data.h"
#include "core/error.h"

namespace wheelpose::body {
namespace {

using testing::body_data;

Eigen::AlignedBox3f box_of(const std::vector<Eigen::Vector3f>& points) {
  Eigen::AlignedBox3f b;
  for (const auto& p : points) b.extend(p);
  return b;
}

TEST(Proxy, ListsAndParsesTheSharedAssets) {
  const auto root = body_data().model().root();
  const auto clothes = list_proxies(root, "clothes");
  ASSERT_FALSE(clothes.empty());
  EXPECT_NE(std::find(clothes.begin(), clothes.end(), "clothes/shoes01"), clothes.end());
  const Proxy& shoes = body_data().proxies().get("clothes/shoes01");
  EXPECT_EQ(shoes.name, "clothes/shoes01");
  EXPECT_GT(shoes.refs.size(), 100u);
  EXPECT_EQ(shoes.refs.size(), shoes.weights.size());
  EXPECT_FALSE(shoes.delete_verts.empty());
  for (const auto& w : shoes.weights) EXPECT_NEAR(w.sum(), 1.0f, 0.05f);
  EXPECT_EQ(&body_data().proxies().get("clothes/shoes01"), &shoes);  // cached
  EXPECT_THROW(body_data().proxies().get("clothes/no_such_suit"), Error);
}

TEST(Proxy, ClothesFollowThePosedBodyAndHideTheSkinTheyCover) {
  PersonSpec bare = sample_spec(21);
  PersonSpec dressed = bare;
  dressed.proxies = {"clothes/male_casualsuit01", "clothes/shoes01", "hair/short02"};
  const Person a = build_person(body_data(), bare), b = build_person(body_data(), dressed);
  ASSERT_EQ(b.garments.size(), 3u);
  EXPECT_LT(b.triangles.size(), a.triangles.size() * 4 / 5);  // the suit hides skin under it
  const Eigen::AlignedBox3f body = box_of(b.vertices);
  for (const Garment& g : b.garments) {
    ASSERT_FALSE(g.triangles.empty()) << g.name;
    const Eigen::AlignedBox3f box = box_of(g.vertices);
    // On the body, a few centimetres proud of it at most.
    EXPECT_TRUE(body.exteriorDistance(box.min()) < 0.08f && body.exteriorDistance(box.max()) < 0.08f)
        << g.name;
  }
  // The shoes sit at the feet: below the knees, near the ankles.
  const Eigen::AlignedBox3f shoes = box_of(b.garments[1].vertices);
  EXPECT_LT(shoes.max().y(), b.coco[13].y());
  EXPECT_LT(shoes.exteriorDistance(b.coco[15]), 0.06f);
  // Hair on the head.
  EXPECT_LT(box_of(b.garments[2].vertices).exteriorDistance(b.coco[0]), 0.12f);
}

TEST(Proxy, GarmentsOnARemovedLimbAreDropped) {
  PersonSpec spec = sample_spec(21);
  spec.proxies = {"clothes/shoes01"};
  const std::size_t both = build_person(body_data(), spec).garments[0].triangles.size();
  spec.limbs[static_cast<int>(Limb::kLeftLeg)] = Cut::kBelow;
  const std::size_t one = build_person(body_data(), spec).garments[0].triangles.size();
  EXPECT_LT(one, both * 2 / 3);
  EXPECT_GT(one, both / 3);
}

}  // namespace
}  // namespace wheelpose::body
