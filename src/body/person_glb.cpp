#include "body/person_glb.h"

#include <string>

#include "body/glb_parts.h"
#include "motion/glb_file.h"

namespace wheelpose::body {

namespace fs = std::filesystem;

namespace {

void export_parts(SceneParts& parts, const fs::path& path) {
  motion::write_glb_file(*assemble_scene(parts, "wheelpose_body_root"), path);
}

}  // namespace

void write_person_glb(const Person& person, const BodyData& /*data*/, const fs::path& path) {
  SceneParts parts;
  add_body_mesh(parts, person.vertices, person.triangles, person.skin);
  add_chair(parts, person.chair);
  add_primitives(parts, person.aid.parts, person.aid.colours, "mobility_aid", aid_material_names());
  for (const Garment& g : person.garments) add_garment_mesh(parts, g, g.vertices);
  for (int k = 0; k < kCocoCount; ++k) {
    if (!person.coco_present[k]) continue;
    parts.markers.emplace_back(std::string("kp_") + coco_names()[k], person.coco[k]);
  }
  parts.markers.emplace_back("kp_left_hip_raised", person.annotated[11]);
  parts.markers.emplace_back("kp_right_hip_raised", person.annotated[12]);
  export_parts(parts, path);
}

void write_wheelchair_glb(const Wheelchair& chair, const fs::path& path) {
  SceneParts parts;
  add_chair(parts, chair);
  export_parts(parts, path);
}

void write_cc_by_wheelchair_glb(const fs::path& path) {
  const TriMesh mesh = load_cc_by_wheelchair();
  SceneParts parts;
  add_mesh(parts, "cc_by_wheelchair", mesh.vertices, vertex_normals(mesh.vertices, mesh.triangles),
           mesh.triangles, "cc_by_wheelchair_material", {0.4f, 0.4f, 0.42f});
  export_parts(parts, path);
}

}  // namespace wheelpose::body
