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

TEST(Furniture, MissingArchiveGivesAnEmptyCatalog) {
  EXPECT_TRUE(FurnitureCatalog("/nonexistent/furniture.sh3f").items().empty());
}

}  // namespace
}  // namespace wheelpose::generate
