#pragma once
// Furniture for rooms: the CC0 models of Debian `sweethome3d-furniture` (archive
// BlendSwap-CC-0.sh3f), read from its catalog (PluginFurnitureCatalog.properties): indoor
// categories only, no doors or windows, nothing under 30 cm or over 2.5 m. Each model is scaled
// to its catalogued width × height × depth, centred in x and z, standing on y = 0. After them,
// from a second archive (KatorLegaz.sh3f, CC-BY 3.0 US, credited in the README), the models
// named "Hanging clothes": coats and shirts on hangers, for the HangingClothes randomizer.

#include <Eigen/Core>
#include <filesystem>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "body/wheelchair.h"

namespace wheelpose::generate {

struct FurnitureItem {
  std::string name, category, creator, entry;      // entry: model path inside the archive
  Eigen::Vector3f size = Eigen::Vector3f::Ones();  // metres: width (x), height (y), depth (z)
  std::filesystem::path archive;                   // the .sh3f file it comes from
  float elevation = 0;  // metres above the floor it hangs at (hanging clothes only)
};

class FurnitureCatalog {
 public:
  // An empty catalog when an archive is absent (rooms then use box stand-ins; no clothes).
  explicit FurnitureCatalog(const std::filesystem::path& archive,
                            const std::filesystem::path& clothes_archive = {});
  static std::filesystem::path default_archive();
  static std::filesystem::path default_clothes_archive();

  // The furniture first (indices 0 … furniture_count() − 1), then the hanging clothes.
  const std::vector<FurnitureItem>& items() const { return items_; }
  int furniture_count() const { return furniture_count_; }
  std::vector<int> hanging_clothes() const;  // their indices into items()
  const std::filesystem::path& archive() const { return archive_; }
  // The model of item i, loaded on first use (thread-safe); throws Error naming the entry.
  const body::TriMesh& mesh(std::size_t i) const;

 private:
  std::filesystem::path archive_;
  std::vector<FurnitureItem> items_;
  int furniture_count_ = 0;
  mutable std::mutex mutex_;
  mutable std::vector<std::unique_ptr<body::TriMesh>> meshes_;
};

}  // namespace wheelpose::generate
