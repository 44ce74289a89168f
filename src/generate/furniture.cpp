// Reading the sweethome3d CC0 furniture catalog and its OBJ models.

#include "generate/furniture.h"

#include <map>
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

}  // namespace

std::filesystem::path FurnitureCatalog::default_archive() {
  return "/usr/share/sweethome3d/furniture/BlendSwap-CC-0.sh3f";
}

FurnitureCatalog::FurnitureCatalog(const std::filesystem::path& archive) : archive_(archive) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(archive, ec)) return;
  // key#N=value lines; one catalog entry per N.
  std::map<int, std::map<std::string, std::string>> entries;
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
  for (auto& [index, e] : entries) {
    if (!indoor(e["category"]) || e["doorOrWindow"] == "true" || e.count("modelRotation") ||
        e["model"].empty()) {
      continue;
    }
    FurnitureItem item;
    item.name = e["name"];
    item.category = e["category"];
    item.creator = e["creator"];
    item.entry = e["model"][0] == '/' ? e["model"].substr(1) : e["model"];
    try {
      item.size =
          Eigen::Vector3f(std::stof(e["width"]), std::stof(e["height"]), std::stof(e["depth"])) *
          0.01f;
    } catch (const std::exception&) {
      continue;
    }
    if (item.size.maxCoeff() < 0.3f || item.size.maxCoeff() > 2.5f || item.size.minCoeff() <= 0)
      continue;
    items_.push_back(std::move(item));
  }
  meshes_.resize(items_.size());
}

const body::TriMesh& FurnitureCatalog::mesh(std::size_t i) const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (meshes_.at(i)) return *meshes_[i];
  const FurnitureItem& item = items_[i];
  body::TriMesh m = body::parse_obj_mesh(body::read_zip_entry(archive_, item.entry),
                                         archive_.string() + ": " + item.entry);
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
