// The sweethome3d CC0 furniture catalog: indoor models only, scaled to their catalogued size.

#include "generate/furniture.h"

#include <gtest/gtest.h>

namespace wheelpose::generate {
namespace {

TEST(Furniture, ModelsStandOnTheFloorAtTheirCataloguedSize) {
  const FurnitureCatalog catalog(FurnitureCatalog::default_archive());
  if (catalog.items().empty()) GTEST_SKIP() << "sweethome3d-furniture is not installed";
  EXPECT_GT(catalog.items().size(), 40u);
  for (std::size_t i = 0; i < catalog.items().size(); i += 7) {
    const FurnitureItem& item = catalog.items()[i];
    EXPECT_NE(item.category, "Exterior") << item.name;
    const body::TriMesh& m = catalog.mesh(i);
    Eigen::Vector3f lo = m.vertices[0], hi = m.vertices[0];
    for (const auto& v : m.vertices) {
      lo = lo.cwiseMin(v);
      hi = hi.cwiseMax(v);
    }
    EXPECT_NEAR(lo.y(), 0.0f, 1e-4f) << item.name;
    EXPECT_NEAR(lo.x() + hi.x(), 0.0f, 1e-3f) << item.name;
    EXPECT_TRUE((hi - lo).isApprox(item.size, 1e-3f)) << item.name;
    EXPECT_EQ(&catalog.mesh(i), &m);  // loaded once
  }
}

TEST(Furniture, HangingClothesFollowTheFurnitureAndHangAtTheirHeight) {
  const FurnitureCatalog furniture(FurnitureCatalog::default_archive());
  const FurnitureCatalog both(FurnitureCatalog::default_archive(),
                              FurnitureCatalog::default_clothes_archive());
  if (both.hanging_clothes().empty()) GTEST_SKIP() << "sweethome3d-furniture is not installed";
  // The furniture keeps its indices, so rooms drawn before the clothes existed stay the same.
  EXPECT_EQ(both.furniture_count(), static_cast<int>(furniture.items().size()));
  EXPECT_EQ(furniture.furniture_count(), static_cast<int>(furniture.items().size()));
  EXPECT_TRUE(furniture.hanging_clothes().empty());
  ASSERT_EQ(both.hanging_clothes().size(), 2u);  // the two "Hanging clothes" of KatorLegaz
  for (const int i : both.hanging_clothes()) {
    EXPECT_GE(i, both.furniture_count());
    const FurnitureItem& item = both.items()[static_cast<std::size_t>(i)];
    EXPECT_EQ(item.name, "Hanging clothes");
    EXPECT_EQ(item.archive, FurnitureCatalog::default_clothes_archive());
    EXPECT_GT(item.elevation, 0.1f);  // they hang, 13 and 39 cm above the floor
    EXPECT_GT(item.size.y(), 1.0f);   // as high as a person's coat
    const body::TriMesh& m = both.mesh(static_cast<std::size_t>(i));
    Eigen::Vector3f lo = m.vertices[0], hi = m.vertices[0];
    for (const auto& v : m.vertices) {
      lo = lo.cwiseMin(v);
      hi = hi.cwiseMax(v);
    }
    EXPECT_TRUE((hi - lo).isApprox(item.size, 1e-3f)) << i;
  }
}

TEST(Furniture, MissingArchiveGivesAnEmptyCatalog) {
  EXPECT_TRUE(FurnitureCatalog("/nonexistent/furniture.sh3f").items().empty());
}

}  // namespace
}  // namespace wheelpose::generate
