#pragma once
// Furniture for rooms: the CC0 models of Debian `sweethome3d-furniture` (archive
// BlendSwap-CC-0.sh3f), read from its catalog (PluginFurnitureCatalog.properties): indoor
// categories only, no doors or windows, nothing under 30 cm or over 2.5 m. Each model is scaled
// to its catalogued width × height × depth, centred in x and z, standing on y = 0.

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
};

class FurnitureCatalog {
 public:
  // An empty catalog when the archive is absent (rooms then use box stand-ins).
  explicit FurnitureCatalog(const std::filesystem::path& archive);
  static std::filesystem::path default_archive();

  const std::vector<FurnitureItem>& items() const { return items_; }
  const std::filesystem::path& archive() const { return archive_; }
  // The model of item i, loaded on first use (thread-safe); throws Error naming the entry.
  const body::TriMesh& mesh(std::size_t i) const;

 private:
  std::filesystem::path archive_;
  std::vector<FurnitureItem> items_;
  mutable std::mutex mutex_;
  mutable std::vector<std::unique_ptr<body::TriMesh>> meshes_;
};

}  // namespace wheelpose::generate
