// Reading the sweethome3d CC0 furniture catalog and its OBJ models.

#include "generate/furniture.h"

#include <map>
#include <optional>
#include <sstream>

#include "body/assets.h"
#include "core/error.h"

namespace wheelpose::generate {
namespace {

bool indoor(const std::string& category) {
  for (const char* c : {"Living room", "Bedroom", "Kitchen", "Office", "Bathroom"}) {
    if (category == c) return true;
  }
  return false;
}

// An archive's catalog entries: key#N=value lines, one entry per N; none when it is absent.
std::map<int, std::map<std::string, std::string>> catalog_entries(
    const std::filesystem::path& archive) {
  std::map<int, std::map<std::string, std::string>> entries;
  std::error_code ec;
  if (archive.empty() || !std::filesystem::is_regular_file(archive, ec)) return entries;
  std::istringstream in(body::read_zip_entry(archive, "PluginFurnitureCatalog.properties"));
  std::string line;
  while (std::getline(in, line)) {
    const auto hash = line.find('#'), eq = line.find('=');
    if (line.empty() || line[0] == '#' || hash == std::string::npos || eq == std::string::npos ||
        hash > eq) {
      continue;
    }
    try {
      entries[std::stoi(line.substr(hash + 1, eq - hash - 1))][line.substr(0, hash)] =
          line.substr(eq + 1);
    } catch (const std::exception&) {
      continue;  // not an entry key
    }
  }
  return entries;
}

// The entry as an item (centimetres to metres); none without a model or a usable size.
std::optional<FurnitureItem> catalog_item(std::map<std::string, std::string>& e,
                                          const std::filesystem::path& archive) {
  if (e["model"].empty() || e.count("modelRotation")) return std::nullopt;
  FurnitureItem item;
  item.name = e["name"];
  item.category = e["category"];
  item.creator = e["creator"];
  item.entry = e["model"][0] == '/' ? e["model"].substr(1) : e["model"];
  item.archive = archive;
  try {
    item.size =
        Eigen::Vector3f(std::stof(e["width"]), std::stof(e["height"]), std::stof(e["depth"])) *
        0.01f;
  } catch (const std::exception&) {
    return std::nullopt;
  }
  if (item.size.maxCoeff() < 0.3f || item.size.maxCoeff() > 2.5f || item.size.minCoeff() <= 0)
    return std::nullopt;
  return item;
}

}  // namespace

FurnitureCatalog::FurnitureCatalog(const std::filesystem::path& archive,
                                   const std::filesystem::path& clothes_archive)
    : archive_(archive) {
  for (auto& [index, e] : catalog_entries(archive)) {
    if (!indoor(e["category"]) || e["doorOrWindow"] == "true") continue;
    if (auto item = catalog_item(e, archive)) items_.push_back(std::move(*item));
  }
  furniture_count_ = static_cast<int>(items_.size());
  for (auto& [index, e] : catalog_entries(clothes_archive)) {
    if (e["name"] != "Hanging clothes") continue;
    auto item = catalog_item(e, clothes_archive);
    if (!item) continue;
    try {
      item->elevation = e.count("elevation") ? std::stof(e["elevation"]) * 0.01f : 0.0f;
    } catch (const std::exception&) {
      continue;
    }
    items_.push_back(std::move(*item));
  }
  meshes_.resize(items_.size());
}

std::filesystem::path FurnitureCatalog::default_archive() {
  return "/usr/share/sweethome3d/furniture/BlendSwap-CC-0.sh3f";
}

std::filesystem::path FurnitureCatalog::default_clothes_archive() {
  return "/usr/share/sweethome3d/furniture/KatorLegaz.sh3f";
}

std::vector<int> FurnitureCatalog::hanging_clothes() const {
  std::vector<int> out;
  for (int i = furniture_count_; i < static_cast<int>(items_.size()); ++i) out.push_back(i);
  return out;
}

const body::TriMesh& FurnitureCatalog::mesh(std::size_t i) const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (meshes_.at(i)) return *meshes_[i];
  const FurnitureItem& item = items_[i];
  body::TriMesh m = body::parse_obj_mesh(body::read_zip_entry(item.archive, item.entry),
                                         item.archive.string() + ": " + item.entry);
  Eigen::Vector3f lo = m.vertices[0], hi = m.vertices[0];
  for (const auto& v : m.vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  const Eigen::Vector3f extent = (hi - lo).cwiseMax(Eigen::Vector3f::Constant(1e-6f));
  const Eigen::Vector3f scale = item.size.cwiseQuotient(extent);
  for (auto& v : m.vertices) {
    const Eigen::Vector3f centred((v.x() - (lo.x() + hi.x()) / 2), v.y() - lo.y(),
                                  v.z() - (lo.z() + hi.z()) / 2);
    v = centred.cwiseProduct(scale);
  }
  meshes_[i] = std::make_unique<body::TriMesh>(std::move(m));
  return *meshes_[i];
}

}  // namespace wheelpose::generate
