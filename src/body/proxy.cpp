// Reading and fitting MakeHuman .mhclo proxies.

#include "body/proxy.h"

#include <algorithm>
#include <sstream>

#include "body/assets.h"
#include "core/error.h"
#include "core/random.h"

namespace wheelpose::body {
namespace {

namespace fs = std::filesystem;
using Eigen::Vector3f;

std::vector<std::array<unsigned, 3>> obj_triangles(const std::string& text, const std::string& where,
                                                   std::size_t vertex_count) {
  std::vector<std::array<unsigned, 3>> triangles;
  std::istringstream in(text);
  std::string line;
  int line_no = 0;
  std::size_t vertices = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.rfind("v ", 0) == 0) ++vertices;
    if (line.rfind("f ", 0) != 0) continue;
    std::istringstream ls(line.substr(2));
    std::vector<unsigned> idx;
    std::string token;
    while (ls >> token) {
      const long i = std::strtol(token.c_str(), nullptr, 10);
      if (i < 1 || static_cast<std::size_t>(i) > vertex_count)
        throw Error(where + ":" + std::to_string(line_no) + ": face index out of range");
      idx.push_back(static_cast<unsigned>(i - 1));
    }
    for (std::size_t k = 2; k < idx.size(); ++k) triangles.push_back({idx[0], idx[k - 1], idx[k]});
  }
  if (vertices != vertex_count) {
    throw Error(where + ": " + std::to_string(vertices) + " vertices but the .mhclo has " +
                std::to_string(vertex_count));
  }
  return triangles;
}

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
  p.triangles = obj_triangles(read_asset(obj), obj.string(), p.refs.size());
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

std::vector<std::string> sample_outfit(const fs::path& root, double gender, std::uint64_t seed) {
  RandomStream rng(seed, {"outfit"});
  std::vector<std::string> suits, shoes;
  const std::string sex = gender >= 0.5 ? "clothes/male_" : "clothes/female_";
  for (const std::string& c : list_proxies(root, "clothes")) {
    if (c.find("shoes") != std::string::npos) shoes.push_back(c);
    else if (c.rfind(sex, 0) == 0) suits.push_back(c);
  }
  const std::vector<std::string> hair = list_proxies(root, "hair");
  const std::vector<std::string> brows = list_proxies(root, "eyebrows");
  auto pick = [&rng](const std::vector<std::string>& from) {
    const double u = rng.uniform01();  // drawn even for an empty list: later draws stay put
    return from.empty() ? std::string()
                        : from[std::min(from.size() - 1, static_cast<std::size_t>(u * from.size()))];
  };
  std::vector<std::string> out;
  const bool has_hair = rng.bernoulli(0.85);
  for (const std::string& p : {pick(suits), pick(shoes), has_hair ? pick(hair) : std::string(),
                               pick(brows)}) {
    if (!p.empty()) out.push_back(p);
  }
  std::error_code ec;
  if (fs::is_regular_file(root / "eyes/low-poly/low-poly.mhclo", ec)) out.push_back("eyes/low-poly");
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
