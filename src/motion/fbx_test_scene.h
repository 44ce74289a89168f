#pragma once
// Header-only helper for FBX tests: a document's objects by id and its connections, with what a
// reader does to play it back: curves evaluated linearly (KeyAttrFlags 24836) and models'
// world transforms from their Lcl Translation/Rotation in their RotationOrder. Written from the
// format's conventions, not from the writer (fbx_scene.h), so tests check what readers see.

#include <Eigen/Geometry>
#include <algorithm>
#include <functional>
#include <map>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "motion/euler_curves.h"
#include "motion/fbx_node.h"

namespace wheelpose::motion::fbx::testing {

inline const Node& child(const Node& node, std::string_view name) {
  const Node* found = node.find(name);
  if (found == nullptr) throw std::runtime_error("no " + std::string(name) + " in " + node.name);
  return *found;
}

inline const Node& top(const std::vector<Node>& document, std::string_view name) {
  for (const Node& node : document) {
    if (node.name == name) return node;
  }
  throw std::runtime_error("no top-level " + std::string(name));
}

template <typename T>
const T& value(const Node& node, std::size_t i = 0) {
  return std::get<T>(node.properties.at(i));
}

// The P entry called `name` in a Properties70 node.
inline const Node& property(const Node& properties70, std::string_view name) {
  for (const Node& p : properties70.children) {
    if (value<std::string>(p) == name) return p;
  }
  throw std::runtime_error("no property " + std::string(name));
}

// An object's name without its class.
inline std::string name_of(const Node& object) {
  const std::string& full = value<std::string>(object, 1);
  return full.substr(0, full.find('\0'));
}

// A column-major 4×4 matrix node (Transform, TransformLink, Matrix).
inline Eigen::Affine3d matrix_of(const Node& node) {
  const auto& m = value<std::vector<double>>(node);
  if (m.size() != 16) throw std::runtime_error(node.name + " is not a 4x4 matrix");
  Eigen::Matrix4d matrix;
  for (int i = 0; i < 16; ++i) matrix(i % 4, i / 4) = m[static_cast<std::size_t>(i)];
  return Eigen::Affine3d(matrix);
}

// Linear interpolation of one AnimationCurve at `tick`, held before the first and after the last
// key: what an FBX reader does with KeyAttrFlags 24836.
inline double evaluate(const Node& curve, std::int64_t tick) {
  const auto& times = value<std::vector<std::int64_t>>(child(curve, "KeyTime"));
  const auto& values = value<std::vector<float>>(child(curve, "KeyValueFloat"));
  if (tick <= times.front()) return values.front();
  if (tick >= times.back()) return values.back();
  const std::size_t k = static_cast<std::size_t>(
      std::upper_bound(times.begin(), times.end(), tick) - times.begin() - 1);
  const double w =
      static_cast<double>(tick - times[k]) / static_cast<double>(times[k + 1] - times[k]);
  return values[k] + w * (values[k + 1] - values[k]);
}

// Objects by id, and connections, of a document: enough to play its animation back.
struct FbxScene {
  std::vector<Node> document;
  std::map<std::int64_t, const Node*> objects;
  struct Link {
    std::int64_t child, parent;
    std::string property;
  };
  std::vector<Link> links;

  FbxScene(const FbxScene&) = delete;  // objects point into document
  explicit FbxScene(std::vector<Node> nodes) : document(std::move(nodes)) {
    for (const Node& object : top(document, "Objects").children) {
      objects[value<std::int64_t>(object)] = &object;
    }
    for (const Node& c : top(document, "Connections").children) {
      links.push_back({value<std::int64_t>(c, 1), value<std::int64_t>(c, 2),
                       c.properties.size() > 3 ? value<std::string>(c, 3) : ""});
    }
  }
  std::vector<const Node*> of_type(std::string_view type) const {
    std::vector<const Node*> found;
    for (const auto& [id, node] : objects) {
      if (node->name == type) found.push_back(node);
    }
    return found;
  }
  // The objects of type `type` linked to `parent`, with the property each links through.
  std::vector<std::pair<const Node*, std::string>> children_of(std::int64_t parent,
                                                               std::string_view type) const {
    std::vector<std::pair<const Node*, std::string>> found;
    for (const Link& link : links) {
      if (link.parent == parent && objects.count(link.child) &&
          objects.at(link.child)->name == type) {
        found.emplace_back(objects.at(link.child), link.property);
      }
    }
    return found;
  }
  std::int64_t parent_of(std::int64_t child) const {
    for (const Link& link : links) {
      if (link.child == child && link.property.empty()) return link.parent;
    }
    return -1;
  }
};

// World transforms of every Model at `tick`, evaluating the curves as the FBX SDK would.
inline std::map<std::int64_t, Eigen::Isometry3d> world_transforms(const FbxScene& scene,
                                                                  std::int64_t tick) {
  constexpr double kDegrees = 180.0 / 3.14159265358979323846;
  std::map<std::int64_t, Eigen::Isometry3d> world;
  std::function<Eigen::Isometry3d(std::int64_t)> world_of = [&](std::int64_t id) {
    if (id == 0) return Eigen::Isometry3d::Identity();
    if (auto it = world.find(id); it != world.end()) return it->second;
    const Node& model = *scene.objects.at(id);
    const Node& p = child(model, "Properties70");
    const auto& t = property(p, "Lcl Translation");
    Eigen::Vector3d translation(value<double>(t, 4), value<double>(t, 5), value<double>(t, 6));
    Eigen::Vector3d rotation = Eigen::Vector3d::Zero();
    for (const auto& [curve_node, target] : scene.children_of(id, "AnimationCurveNode")) {
      Eigen::Vector3d v;
      for (const auto& [curve, channel] :
           scene.children_of(value<std::int64_t>(*curve_node), "AnimationCurve")) {
        v[channel.back() - 'X'] = evaluate(*curve, tick);
      }
      (target == "Lcl Translation" ? translation : rotation) = v;
    }
    const auto order =
        static_cast<EulerOrder>(value<std::int32_t>(property(p, "RotationOrder"), 4));
    Eigen::Isometry3d local = Eigen::Isometry3d::Identity();
    local.translate(translation);
    local.rotate(euler_rotation(rotation / kDegrees, order));
    const Eigen::Isometry3d result = world_of(scene.parent_of(id)) * local;
    world[id] = result;
    return result;
  };
  for (const Node* model : scene.of_type("Model")) world_of(value<std::int64_t>(*model));
  return world;
}

}  // namespace wheelpose::motion::fbx::testing
