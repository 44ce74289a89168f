// Reading and fitting MakeHuman .mhclo proxies.

#include "body/proxy.h"

#include <algorithm>
#include <sstream>

#include "body/assets.h"
#include "body/wheelchair.h"
#include "core/error.h"

namespace wheelpose::body {
namespace {

namespace fs = std::filesystem;
using Eigen::Vector3f;

// A frame of a reference triangle: two edges and the unit normal.
Eigen::Matrix3f triangle_frame(const Vector3f& a, const Vector3f& b, const Vector3f& c) {
  Eigen::Matrix3f m;
  m.col(0) = b - a;
  m.col(1) = c - a;
  const Vector3f n = m.col(0).cross(m.col(1));
  const float len = n.norm();
  m.col(2) = len > 1e-12f ? Vector3f(n / len) : Vector3f::UnitZ();
  return m;
}

}  // namespace

Proxy load_proxy(const fs::path& mhclo) {
  const std::string text = read_asset(mhclo);
  Proxy p;
  p.name = mhclo.parent_path().parent_path().filename().string() + "/" + mhclo.stem().string();
  std::istringstream in(text);
  std::string line, obj_file;
  int line_no = 0;
  enum { kHeader, kVerts, kDelete } section = kHeader;
  const std::string where = mhclo.string();
  auto fail = [&](const std::string& what) {
    throw Error(where + ":" + std::to_string(line_no) + ": " + what);
  };
  while (std::getline(in, line)) {
    ++line_no;
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ls(line);
    if (section == kVerts) {
      if (line.rfind("delete_verts", 0) == 0) {
        section = kDelete;
        continue;
      }
      std::array<int, 3> r{};
      Vector3f w = Vector3f::Zero(), o = Vector3f::Zero();
      if (!(ls >> r[0])) continue;
      if (!(ls >> r[1] >> r[2])) {  // a single index: the vertex follows it exactly
        r[1] = r[2] = r[0];
        w = Vector3f(1, 0, 0);
      } else if (!(ls >> w.x() >> w.y() >> w.z() >> o.x() >> o.y() >> o.z())) {
        fail("expected 3 vertices, 3 weights and 3 offsets");
      }
      p.refs.push_back(r);
      p.weights.push_back(w);
      p.offsets.push_back(o);
      continue;
    }
    if (section == kDelete) {
      std::vector<std::string> tokens;
      for (std::string t; ls >> t;) tokens.push_back(t);
      for (std::size_t i = 0; i < tokens.size(); ++i) {
        if (i + 2 < tokens.size() && tokens[i + 1] == "-") {
          const int a = std::stoi(tokens[i]), b = std::stoi(tokens[i + 2]);
          for (int v = a; v <= b; ++v) p.delete_verts.push_back(v);
          i += 2;
        } else {
          p.delete_verts.push_back(std::stoi(tokens[i]));
        }
      }
      continue;
    }
    std::string key;
    ls >> key;
    if (key == "obj_file") {
      ls >> obj_file;
    } else if (key == "x_scale" || key == "y_scale" || key == "z_scale") {
      auto& s = p.scales[static_cast<std::size_t>(key[0] - 'x')];
      if (!(ls >> s[0] >> s[1] >> s[2]) || s[2] <= 0) fail(key + ": expected vertex vertex reference");
    } else if (key == "verts") {
      section = kVerts;
    } else if (key == "delete_verts") {
      section = kDelete;
    }
  }
  if (obj_file.empty()) throw Error(where + ": no obj_file");
  if (p.refs.empty()) throw Error(where + ": no verts section");
  const fs::path obj = mhclo.parent_path() / obj_file;
  const TriMesh mesh = parse_obj_mesh(read_asset(obj), obj.string());
  if (mesh.vertices.size() != p.refs.size()) {
    throw Error(obj.string() + ": " + std::to_string(mesh.vertices.size()) +
                " vertices but the .mhclo has " + std::to_string(p.refs.size()));
  }
  p.triangles = mesh.triangles;
  return p;
}

std::vector<Vector3f> fit_proxy(const Proxy& p, const std::vector<Vector3f>& rest,
                                const std::vector<Vector3f>& posed) {
  const int n = static_cast<int>(rest.size());
  auto check = [&](int v) {
    if (v < 0 || v >= n) throw Error(p.name + ": base vertex " + std::to_string(v) + " out of range");
  };
  // Offsets are in base-mesh decimetres for the reference body; scale them to this body (metres).
  Vector3f scale = Vector3f::Constant(0.1f);
  for (int axis = 0; axis < 3; ++axis) {
    const auto& s = p.scales[static_cast<std::size_t>(axis)];
    if (s[2] <= 0) continue;
    const int a = static_cast<int>(s[0]), b = static_cast<int>(s[1]);
    check(a);
    check(b);
    scale[axis] = std::abs(rest[a][axis] - rest[b][axis]) / s[2];
  }
  std::vector<Vector3f> out(p.refs.size());
  for (std::size_t i = 0; i < p.refs.size(); ++i) {
    const auto& r = p.refs[i];
    for (int v : r) check(v);
    const Vector3f& w = p.weights[i];
    const Vector3f offset = p.offsets[i].cwiseProduct(scale);
    const Vector3f posed_point = w[0] * posed[r[0]] + w[1] * posed[r[1]] + w[2] * posed[r[2]];
    if (offset.squaredNorm() == 0 || r[0] == r[1]) {
      out[i] = posed_point + offset;
      continue;
    }
    // Express the offset in the rest triangle's frame, rebuild it in the posed one.
    const Eigen::Matrix3f rest_frame = triangle_frame(rest[r[0]], rest[r[1]], rest[r[2]]);
    const Eigen::Matrix3f posed_frame = triangle_frame(posed[r[0]], posed[r[1]], posed[r[2]]);
    const Vector3f local = rest_frame.inverse() * offset;
    out[i] = posed_point + posed_frame * local;
  }
  return out;
}

std::vector<std::string> list_proxies(const fs::path& makehuman_root, const std::string& folder) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(makehuman_root / folder, ec)) {
    const fs::path mhclo = e.path() / (e.path().filename().string() + ".mhclo");
    if (fs::is_regular_file(mhclo, ec)) names.push_back(folder + "/" + e.path().filename().string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

ProxyCatalog ProxyCatalog::scan(const fs::path& root) {
  ProxyCatalog c;
  for (const std::string& name : list_proxies(root, "clothes")) {
    if (name.find("shoes") != std::string::npos) c.shoes.push_back(name);
    else if (name.rfind("clothes/male_", 0) == 0) c.male_suits.push_back(name);
    else if (name.rfind("clothes/female_", 0) == 0) c.female_suits.push_back(name);
    else c.hats.push_back(name);
  }
  c.hair = list_proxies(root, "hair");
  c.eyebrows = list_proxies(root, "eyebrows");
  c.eyes = list_proxies(root, "eyes");
  return c;
}

std::string pick_proxy(RandomStream& rng, const std::vector<std::string>& from) {
  const double u = rng.uniform01();
  return from.empty() ? std::string()
                      : from[std::min(from.size() - 1, static_cast<std::size_t>(u * from.size()))];
}

std::vector<std::string> sample_outfit(const fs::path& root, double gender, std::uint64_t seed) {
  RandomStream rng(seed, {"outfit"});
  const ProxyCatalog catalog = ProxyCatalog::scan(root);
  const auto& suits = gender >= 0.5 ? catalog.male_suits : catalog.female_suits;
  std::vector<std::string> out;
  const bool has_hair = rng.bernoulli(0.85);
  for (const std::string& p :
       {pick_proxy(rng, suits), pick_proxy(rng, catalog.shoes),
        has_hair ? pick_proxy(rng, catalog.hair) : std::string(), pick_proxy(rng, catalog.eyebrows)}) {
    if (!p.empty()) out.push_back(p);
  }
  if (std::find(catalog.eyes.begin(), catalog.eyes.end(), "eyes/low-poly") != catalog.eyes.end())
    out.push_back("eyes/low-poly");
  return out;
}

const Proxy& ProxyLibrary::get(const std::string& name) const {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = cache_.find(name);
    if (it != cache_.end()) return *it->second;
  }
  const fs::path dir = root_ / name;
  auto loaded = std::make_unique<Proxy>(load_proxy(dir / (dir.filename().string() + ".mhclo")));
  std::lock_guard<std::mutex> lock(mutex_);
  auto [it, inserted] = cache_.emplace(name, std::move(loaded));
  return *it->second;
}

}  // namespace wheelpose::body
