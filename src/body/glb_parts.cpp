#include "body/glb_parts.h"

#include <algorithm>

#include "body/person.h"

namespace wheelpose::body {

SceneParts::~SceneParts() {
  for (aiMesh* mesh : meshes) delete mesh;
  for (aiMaterial* material : materials) delete material;
}

aiVector3D ai(const Eigen::Vector3f& v) { return aiVector3D(v.x(), v.y(), v.z()); }

std::size_t add_mesh(SceneParts& parts, const std::string& name,
                     const std::vector<Eigen::Vector3f>& vertices,
                     const std::vector<Eigen::Vector3f>& normals,
                     const std::vector<std::array<unsigned, 3>>& triangles,
                     const std::string& material, const Eigen::Vector3f& colour) {
  auto* m = new aiMaterial;
  const aiString material_name(material);
  m->AddProperty(&material_name, AI_MATKEY_NAME);
  const aiColor4D c(colour.x(), colour.y(), colour.z(), 1.0f);
  m->AddProperty(&c, 1, AI_MATKEY_COLOR_DIFFUSE);
  parts.materials.push_back(m);

  auto* mesh = new aiMesh;
  mesh->mName = name;
  mesh->mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
  mesh->mMaterialIndex = static_cast<unsigned>(parts.materials.size() - 1);
  mesh->mNumVertices = static_cast<unsigned>(vertices.size());
  mesh->mVertices = new aiVector3D[vertices.size()];
  mesh->mNormals = new aiVector3D[vertices.size()];
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    mesh->mVertices[i] = ai(vertices[i]);
    mesh->mNormals[i] = ai(normals[i]);
  }
  mesh->mNumFaces = static_cast<unsigned>(triangles.size());
  mesh->mFaces = new aiFace[triangles.size()];
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    mesh->mFaces[i].mNumIndices = 3;
    mesh->mFaces[i].mIndices = new unsigned[3]{triangles[i][0], triangles[i][1], triangles[i][2]};
  }
  parts.meshes.push_back(mesh);
  return parts.meshes.size() - 1;
}

std::size_t add_body_mesh(SceneParts& parts, const std::vector<Eigen::Vector3f>& vertices,
                          const std::vector<std::array<unsigned, 3>>& triangles,
                          const Eigen::Vector3f& skin) {
  return add_mesh(parts, "body", vertices, vertex_normals(vertices, triangles), triangles, "skin",
                  skin);
}

bool add_garment_mesh(SceneParts& parts, const Garment& garment,
                      const std::vector<Eigen::Vector3f>& vertices) {
  if (garment.triangles.empty()) return false;
  const std::string name = garment.name.substr(garment.name.find('/') + 1);
  add_mesh(parts, name, vertices, vertex_normals(vertices, garment.triangles), garment.triangles,
           name + "_material", {0.35f, 0.38f, 0.45f});
  return true;
}

void add_primitives(SceneParts& parts, const std::vector<Primitive>& prims,
                    const std::vector<Eigen::Vector3f>& colours, const std::string& prefix,
                    const std::vector<const char*>& names) {
  for (int m = 0; m < static_cast<int>(colours.size()); ++m) {
    const TriMesh mesh = primitive_mesh(prims, m);
    if (mesh.triangles.empty()) continue;
    const std::string name = prefix + "_" + names[static_cast<std::size_t>(m)];
    add_mesh(parts, name, mesh.vertices, mesh.normals, mesh.triangles, name + "_material",
             colours[m]);
  }
}

void add_chair(SceneParts& parts, const Wheelchair& chair) {
  if (!chair.model.vertices.empty()) {
    add_mesh(parts, "wheelchair_cc_by", chair.model.vertices,
             vertex_normals(chair.model.vertices, chair.model.triangles), chair.model.triangles,
             "wheelchair_cc_by_material", chair.colours[0]);
    return;
  }
  add_primitives(parts, chair.parts, chair.colours, "wheelchair",
                 {"frame", "upholstery", "tyre", "trim"});
}

std::unique_ptr<aiScene> assemble_scene(SceneParts& parts, const std::string& root_name) {
  auto scene = std::make_unique<aiScene>();
  scene->mRootNode = new aiNode(root_name);
  const std::size_t n = parts.meshes.size() + parts.markers.size();
  scene->mRootNode->mNumChildren = static_cast<unsigned>(n);
  scene->mRootNode->mChildren = new aiNode*[n];
  for (std::size_t i = 0; i < parts.meshes.size(); ++i) {
    auto* node = new aiNode(std::string(parts.meshes[i]->mName.C_Str()) + "_node");
    node->mParent = scene->mRootNode;
    node->mNumMeshes = 1;
    node->mMeshes = new unsigned[1]{static_cast<unsigned>(i)};
    scene->mRootNode->mChildren[i] = node;
  }
  for (std::size_t k = 0; k < parts.markers.size(); ++k) {
    auto* node = new aiNode(parts.markers[k].first);
    node->mParent = scene->mRootNode;
    aiMatrix4x4::Translation(ai(parts.markers[k].second), node->mTransformation);
    scene->mRootNode->mChildren[parts.meshes.size() + k] = node;
  }
  // The scene owns the meshes and materials from here on.
  scene->mNumMeshes = static_cast<unsigned>(parts.meshes.size());
  scene->mMeshes = new aiMesh*[parts.meshes.size()];
  std::copy(parts.meshes.begin(), parts.meshes.end(), scene->mMeshes);
  scene->mNumMaterials = static_cast<unsigned>(parts.materials.size());
  scene->mMaterials = new aiMaterial*[parts.materials.size()];
  std::copy(parts.materials.begin(), parts.materials.end(), scene->mMaterials);
  parts.meshes.clear();
  parts.materials.clear();
  return scene;
}

}  // namespace wheelpose::body
