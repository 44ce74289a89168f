#include "scene/primitives.h"

#include <cmath>
#include <numbers>
#include <utility>

#include "core/error.h"

namespace wheelpose::scene {
namespace {

constexpr float kPi = std::numbers::pi_v<float>;

// Appends an n×n grid over the parallelogram origin + s·u + t·v (s, t in [0, 1]).
void add_grid(Mesh& m, const Eigen::Vector3f& origin, const Eigen::Vector3f& u,
              const Eigen::Vector3f& v, int n) {
  const Eigen::Vector3f normal = u.cross(v).normalized();
  const int base = static_cast<int>(m.positions.size());
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      const float s = static_cast<float>(i) / n;
      const float t = static_cast<float>(j) / n;
      m.positions.push_back(origin + s * u + t * v);
      m.normals.push_back(normal);
      m.uvs.emplace_back(s, t);
    }
  }
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const int a = base + j * (n + 1) + i;
      m.triangles.emplace_back(a, a + 1, a + n + 2);
      m.triangles.emplace_back(a, a + n + 2, a + n + 1);
    }
  }
}

// A surface of revolution about Y through rings (polar angle, vertical offset): spheres and
// capsules. UV: u around, v from bottom (0) to top (1).
Mesh revolve(float radius, const std::vector<std::pair<float, float>>& rings, int sectors) {
  Mesh m;
  const int nr = static_cast<int>(rings.size());
  for (int r = 0; r < nr; ++r) {
    const auto [theta, offset] = rings[r];
    for (int s = 0; s <= sectors; ++s) {
      const float phi = 2.0f * kPi * s / sectors;
      const Eigen::Vector3f n(std::sin(theta) * std::sin(phi), std::cos(theta),
                              std::sin(theta) * std::cos(phi));
      m.positions.push_back(radius * n + Eigen::Vector3f(0, offset, 0));
      m.normals.push_back(n);
      m.uvs.emplace_back(static_cast<float>(s) / sectors, 1.0f - static_cast<float>(r) / (nr - 1));
    }
  }
  for (int r = 0; r + 1 < nr; ++r) {
    for (int s = 0; s < sectors; ++s) {
      const int a = r * (sectors + 1) + s;
      const int b = a + sectors + 1;
      // Skip the degenerate triangles at the poles.
      if (rings[r].first > 0.0f) m.triangles.emplace_back(a, b, a + 1);
      if (rings[r + 1].first < kPi) m.triangles.emplace_back(a + 1, b, b + 1);
    }
  }
  return m;
}

}  // namespace

Mesh make_sphere(float radius, int segments) {
  std::vector<std::pair<float, float>> rings;
  for (int r = 0; r <= segments; ++r) rings.emplace_back(kPi * r / segments, 0.0f);
  Mesh m = revolve(radius, rings, 2 * segments);
  m.primitive = PrimitiveSpec{"sphere", Eigen::Vector3f(radius, radius, radius), segments};
  return m;
}

Mesh make_capsule(float radius, float half_height, int segments) {
  const int half = std::max(1, segments / 2);
  std::vector<std::pair<float, float>> rings;
  for (int r = 0; r <= half; ++r) rings.emplace_back(0.5f * kPi * r / half, half_height);
  for (int r = 0; r <= half; ++r)
    rings.emplace_back(0.5f * kPi * (1.0f + float(r) / half), -half_height);
  Mesh m = revolve(radius, rings, 2 * segments);
  m.primitive = PrimitiveSpec{"capsule", Eigen::Vector3f(radius, half_height, radius), segments};
  return m;
}

Mesh make_plane(float half_x, float half_z, int segments) {
  Mesh m;
  // u along +X, v along −Z so that u × v = +Y.
  add_grid(m, Eigen::Vector3f(-half_x, 0, half_z), Eigen::Vector3f(2 * half_x, 0, 0),
           Eigen::Vector3f(0, 0, -2 * half_z), segments);
  m.primitive = PrimitiveSpec{"plane", Eigen::Vector3f(half_x, 0, half_z), segments};
  return m;
}

Mesh make_box(const Eigen::Vector3f& h, int segments) {
  Mesh m;
  const Eigen::Vector3f x(2 * h.x(), 0, 0), y(0, 2 * h.y(), 0), z(0, 0, 2 * h.z());
  add_grid(m, Eigen::Vector3f(-h.x(), -h.y(), h.z()), x, y, segments);   // +Z
  add_grid(m, Eigen::Vector3f(h.x(), -h.y(), -h.z()), -x, y, segments);  // −Z
  add_grid(m, Eigen::Vector3f(h.x(), -h.y(), h.z()), -z, y, segments);   // +X
  add_grid(m, Eigen::Vector3f(-h.x(), -h.y(), -h.z()), z, y, segments);  // −X
  add_grid(m, Eigen::Vector3f(-h.x(), h.y(), h.z()), x, -z, segments);   // +Y
  add_grid(m, Eigen::Vector3f(-h.x(), -h.y(), -h.z()), x, z, segments);  // −Y
  m.primitive = PrimitiveSpec{"box", h, segments};
  return m;
}

Mesh make_primitive(const PrimitiveSpec& spec) {
  if (spec.segments < 1 || spec.segments > 4096) {
    throw Error("primitive '" + spec.type + "': segments must be in 1..4096");
  }
  if ((spec.size.array() < 0.0f).any()) {
    throw Error("primitive '" + spec.type + "': size must not be negative");
  }
  if (spec.type == "sphere") return make_sphere(spec.size.x(), std::max(2, spec.segments));
  if (spec.type == "box") return make_box(spec.size, spec.segments);
  if (spec.type == "plane") return make_plane(spec.size.x(), spec.size.z(), spec.segments);
  if (spec.type == "capsule") {
    return make_capsule(spec.size.x(), spec.size.y(), std::max(2, spec.segments));
  }
  throw Error("unknown primitive type '" + spec.type + "' (sphere, box, plane, capsule)");
}

}  // namespace wheelpose::scene
