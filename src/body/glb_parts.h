#pragma once
// The meshes and materials of the body stage's glb files (static person, empty chair, CC-BY
// chair, rigged person), gathered before they become one Assimp scene. The static and the rigged
// person share these, so both show the colours the renderer uses.

#include <assimp/scene.h>

#include <Eigen/Core>
#include <array>
#include <filesystem>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "body/wheelchair.h"

namespace wheelpose::body {

struct Garment;

// Owns its meshes and materials until assemble_scene hands them to the scene.
struct SceneParts {
  SceneParts() = default;
  SceneParts(const SceneParts&) = delete;
  SceneParts& operator=(const SceneParts&) = delete;
  ~SceneParts();
  std::vector<aiMesh*> meshes;
  std::vector<aiMaterial*> materials;
  std::vector<std::pair<std::string, Eigen::Vector3f>> markers;  // empty nodes at points
};

aiVector3D ai(const Eigen::Vector3f& v);

// Adds a mesh with its own base-colour material (named `material`); returns the mesh's index.
std::size_t add_mesh(SceneParts& parts, const std::string& name,
                     const std::vector<Eigen::Vector3f>& vertices,
                     const std::vector<Eigen::Vector3f>& normals,
                     const std::vector<std::array<unsigned, 3>>& triangles,
                     const std::string& material, const Eigen::Vector3f& colour);

// The body mesh "body" in skin colour.
std::size_t add_body_mesh(SceneParts& parts, const std::vector<Eigen::Vector3f>& vertices,
                          const std::vector<std::array<unsigned, 3>>& triangles,
                          const Eigen::Vector3f& skin);
// A worn proxy, named after it without its folder, in the garments' grey. No mesh (returns
// false) when every face hangs on a removed limb.
bool add_garment_mesh(SceneParts& parts, const Garment& garment,
                      const std::vector<Eigen::Vector3f>& vertices);

// One mesh per material of a primitive assembly, named <prefix>_<material name>.
void add_primitives(SceneParts& parts, const std::vector<Primitive>& prims,
                    const std::vector<Eigen::Vector3f>& colours, const std::string& prefix,
                    const std::vector<const char*>& names);
void add_chair(SceneParts& parts, const Wheelchair& chair);
inline const std::vector<const char*>& aid_material_names() {
  static const std::vector<const char*> names = {"frame", "grips"};
  return names;
}

// A scene whose root `root_name` holds one node "<mesh>_node" per mesh, then the markers.
std::unique_ptr<aiScene> assemble_scene(SceneParts& parts, const std::string& root_name);

}  // namespace wheelpose::body
