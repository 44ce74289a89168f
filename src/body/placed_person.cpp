#include "body/placed_person.h"

#include <algorithm>
#include <cmath>
#include <tuple>
#include <vector>

namespace wheelpose::body {
namespace {

using Eigen::Vector3f;

// The outfit region around each rig bone; the numbering is the order regions are emitted.
enum Region { kSkin = 0, kTop = 1, kBottom = 2, kShoes = 3, kLips = 4 };

Region region_of_bone(const std::string& bone, const DressCode& dress) {
  if (bone.starts_with("head") || bone.starts_with("neck") || bone.starts_with("hand") ||
      bone.starts_with("thumb") || bone.starts_with("index") || bone.starts_with("middle") ||
      bone.starts_with("ring") || bone.starts_with("pinky")) {
    return kSkin;
  }
  if (bone.starts_with("lowerarm")) return dress.long_sleeves ? kTop : kSkin;
  if (bone.starts_with("calf")) return dress.long_trousers ? kBottom : kSkin;
  if (bone.starts_with("foot") || bone.starts_with("ball")) return kShoes;
  if (bone.starts_with("pelvis") || bone.starts_with("thigh")) return kBottom;
  return kTop;
}

float segment_distance2(const Vector3f& p, const Vector3f& a, const Vector3f& b) {
  const Vector3f ab = b - a;
  const float len2 = ab.squaredNorm();
  const float t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0f, 1.0f) : 0.0f;
  return (a + t * ab - p).squaredNorm();
}

// Region per point (of the rest, unposed body) from its nearest bone.
std::vector<Region> nearest_bone_regions(const std::vector<Vector3f>& rest_points,
                                         const Person& person, const Rig& rig,
                                         const DressCode& dress) {
  std::vector<Region> bone_region(rig.bones.size());
  for (std::size_t b = 0; b < rig.bones.size(); ++b)
    bone_region[b] = region_of_bone(rig.bones[b].name, dress);
  std::vector<Region> out(rest_points.size(), kTop);
  for (std::size_t v = 0; v < rest_points.size(); ++v) {
    float best = INFINITY;
    for (std::size_t b = 0; b < rig.bones.size(); ++b) {
      const float d =
          segment_distance2(rest_points[v], person.rest_bones.head[b], person.rest_bones.tail[b]);
      if (d < best) {
        best = d;
        out[v] = bone_region[b];
      }
    }
  }
  return out;
}

std::vector<Region> vertex_regions(const Person& person, const Rig& rig, const DressCode& dress) {
  return nearest_bone_regions(person.rest_vertices, person, rig, dress);
}

bool is_suit(const std::string& garment) {
  return garment.starts_with("clothes/male_") || garment.starts_with("clothes/female_");
}

// Cylindrical UVs around the rest body so procedural fabric wraps it.
Eigen::Vector2f body_uv(const Vector3f& rest) {
  return Eigen::Vector2f(static_cast<float>(std::atan2(rest.x(), rest.z()) / (2 * M_PI) + 0.5),
                         rest.y() / 1.8f);
}

// The triangles whose first vertex passes `keep`, re-indexed into a part of their own: world
// positions and normals, UVs from the rest (unposed) positions.
template <typename Triangles, typename Keep>
PlacedPart cut_part(const std::vector<Vector3f>& world, const std::vector<Vector3f>& normals,
                    const std::vector<Vector3f>& rest, const Triangles& triangles, Keep keep) {
  PlacedPart part;
  std::vector<int> local(world.size(), -1);
  for (const auto& t : triangles) {
    if (!keep(static_cast<int>(t[0]))) continue;
    Eigen::Vector3i tri;
    for (int c = 0; c < 3; ++c) {
      int& l = local[t[c]];
      if (l < 0) {
        l = static_cast<int>(part.positions.size());
        part.positions.push_back(world[t[c]]);
        part.normals.push_back(normals[t[c]]);
        part.uvs.push_back(body_uv(rest[t[c]]));
      }
      tri[c] = l;
    }
    part.triangles.push_back(tri);
  }
  return part;
}

// The body, split into skin and the outfit's top, bottom and shoes: a worn suit covers the body,
// so what shows of it is skin; otherwise the body is painted by bone.
void add_body_regions(const Person& person, const Rig& rig, const DressCode& dress,
                      const Eigen::Affine3f& to_world, std::vector<PlacedPart>& parts) {
  std::vector<Vector3f> world(person.vertices.size());
  for (std::size_t v = 0; v < world.size(); ++v) world[v] = to_world * person.vertices[v];
  const std::vector<Vector3f> normals = vertex_normals(world, person.triangles);
  const bool suited =
      std::any_of(person.garments.begin(), person.garments.end(), [](const Garment& g) {
        return g.name.find("shoes") == std::string::npos && is_suit(g.name);
      });
  std::vector<Region> region = suited ? std::vector<Region>(person.rest_vertices.size(), kSkin)
                                      : vertex_regions(person, rig, dress);
  for (std::size_t v = 0; v < region.size() && v < person.lips.size(); ++v) {
    if (person.lips[v]) region[v] = kLips;
  }
  static const char* kRegionNames[] = {"skin", "top", "bottom", "shoes", "lips"};
  static const Paint kRegionPaint[] = {Paint::kSkin, Paint::kTop, Paint::kBottom, Paint::kShoes,
                                       Paint::kLips};
  for (int r = kSkin; r <= kLips; ++r) {
    PlacedPart part = cut_part(world, normals, person.rest_vertices, person.triangles,
                               [&](int v) { return region[v] == r; });
    part.name = kRegionNames[r];
    part.paint = kRegionPaint[r];
    part.colour = person.skin;
    if (!part.triangles.empty()) parts.push_back(std::move(part));
  }
}

// The whole garment as a part (world positions), its vertices in their own order.
PlacedPart garment_part(const Garment& g, const Eigen::Affine3f& to_world) {
  PlacedPart part;
  part.positions.reserve(g.vertices.size());
  for (const Vector3f& v : g.vertices) part.positions.push_back(to_world * v);
  part.normals = vertex_normals(part.positions, g.triangles);
  for (const Vector3f& r : g.rest_vertices) part.uvs.push_back(body_uv(r));
  for (const auto& t : g.triangles)
    part.triangles.emplace_back(static_cast<int>(t[0]), static_cast<int>(t[1]),
                                static_cast<int>(t[2]));
  return part;
}

// The triangles of `g` whose first vertex passes `keep`, as a part (normals of the whole
// garment, so the cut leaves no seam in the shading).
PlacedPart garment_part(const Garment& g, const Eigen::Affine3f& to_world,
                        const std::vector<char>& keep) {
  std::vector<Vector3f> world(g.vertices.size());
  for (std::size_t v = 0; v < world.size(); ++v) world[v] = to_world * g.vertices[v];
  return cut_part(world, vertex_normals(world, g.triangles), g.rest_vertices, g.triangles,
                  [&](int v) { return keep[v] != 0; });
}

// The MakeHuman clothes, hair, eyebrows and eyes worn, each in the outfit's colour for it. A
// suit is cut by nearest bone into its top (shirt, jacket) and bottom (trousers, skirt), so
// people wear two garments rather than one-colour pyjamas.
void add_garments(const Person& person, const Rig& rig, const DressCode& dress,
                  const Eigen::Affine3f& to_world, std::vector<PlacedPart>& parts) {
  for (const Garment& g : person.garments) {
    if (g.triangles.empty()) continue;
    const std::string name = g.name.substr(g.name.find('/') + 1);
    const bool hair = g.name.starts_with("hair/") || g.name.starts_with("eyebrows/");
    const bool eyes = g.name.starts_with("eyes/");
    const bool shoes = g.name.find("shoes") != std::string::npos;
    if (is_suit(g.name) && !shoes) {
      const std::vector<Region> region = nearest_bone_regions(g.rest_vertices, person, rig, dress);
      std::vector<char> lower(region.size());
      for (std::size_t v = 0; v < region.size(); ++v)
        lower[v] = region[v] == kBottom || region[v] == kShoes;
      std::vector<char> upper(lower.size());
      for (std::size_t v = 0; v < lower.size(); ++v) upper[v] = !lower[v];
      for (const auto& [keep, paint, suffix] : {std::tuple{&upper, Paint::kTop, "_top"},
                                                std::tuple{&lower, Paint::kBottom, "_bottom"}}) {
        PlacedPart part = garment_part(g, to_world, *keep);
        if (part.triangles.empty()) continue;
        part.name = name + suffix;
        part.paint = paint;
        parts.push_back(std::move(part));
      }
      continue;
    }
    PlacedPart part = garment_part(g, to_world);
    part.name = name;
    part.paint = eyes    ? Paint::kEyes
                 : hair  ? Paint::kHair
                 : shoes ? Paint::kShoes
                         : Paint::kBottom;  // hats
    parts.push_back(std::move(part));
  }
}

void add_wheelchair(const Wheelchair& chair, const Eigen::Affine3f& to_world,
                    const std::string& prefix, std::vector<PlacedPart>& parts) {
  static const char* kPartNames[] = {"frame", "upholstery", "tyre", "trim"};
  for (int m = 0; m < 4; ++m) {
    PlacedPart part = placed_mesh(primitive_mesh(chair, m), to_world);
    if (part.triangles.empty()) continue;
    part.name = prefix + kPartNames[m];
    part.owner = PartOwner::kWheelchair;
    part.paint = Paint::kOwnColour;
    part.material = m;
    part.colour = static_cast<std::size_t>(m) < chair.colours.size() ? chair.colours[m]
                                                                     : Vector3f(0.2f, 0.2f, 0.2f);
    parts.push_back(std::move(part));
  }
}

void add_mobility_aid(const MobilityAid& aid, const Eigen::Affine3f& to_world,
                      std::vector<PlacedPart>& parts) {
  static const char* kAidParts[] = {"frame", "grips"};
  for (int m = 0; m < static_cast<int>(aid.colours.size()); ++m) {
    PlacedPart part = placed_mesh(primitive_mesh(aid.parts, m), to_world);
    if (part.triangles.empty()) continue;
    part.name = std::string("mobility_aid_") + kAidParts[m];
    part.owner = PartOwner::kMobilityAid;
    part.paint = Paint::kOwnColour;
    part.material = m;
    part.colour = aid.colours[static_cast<std::size_t>(m)];
    parts.push_back(std::move(part));
  }
}

}  // namespace

PlacedPart placed_mesh(const TriMesh& mesh, const Eigen::Affine3f& to_world) {
  PlacedPart part;
  part.positions.reserve(mesh.vertices.size());
  for (const Vector3f& v : mesh.vertices) part.positions.push_back(to_world * v);
  for (const Vector3f& n : mesh.normals)
    part.normals.push_back((to_world.linear() * n).normalized());
  for (const auto& t : mesh.triangles)
    part.triangles.emplace_back(static_cast<int>(t[0]), static_cast<int>(t[1]),
                                static_cast<int>(t[2]));
  return part;
}

std::vector<PlacedPart> place_person(const Person& person, const Rig& rig, const DressCode& dress,
                                     const Eigen::Affine3f& to_world) {
  std::vector<PlacedPart> parts;
  add_body_regions(person, rig, dress, to_world, parts);
  add_garments(person, rig, dress, to_world, parts);
  add_wheelchair(person.chair, to_world, "wheelchair_", parts);
  add_mobility_aid(person.aid, to_world, parts);
  return parts;
}

std::vector<PlacedPart> place_wheelchair(const Wheelchair& chair, const Eigen::Affine3f& to_world) {
  std::vector<PlacedPart> parts;
  add_wheelchair(chair, to_world, "", parts);
  return parts;
}

}  // namespace wheelpose::body
