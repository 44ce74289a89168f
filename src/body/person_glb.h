#pragma once
// The body stage's static glb exports (`wheelpose body export`): a posed person, an empty
// wheelchair, the CC-BY wheelchair. Meshes and colours come from glb_parts.h, which the rigged
// export shares; files go through motion::write_glb_file (atomic, byte-identical).

#include <filesystem>

#include "body/person.h"

namespace wheelpose::body {

// glb with meshes "body" and "wheelchair_<material>" and one empty node per keypoint; the floor
// is at y = 0. Byte-identical for identical persons.
void write_person_glb(const Person& person, const BodyData& data,
                      const std::filesystem::path& path);
// glb of an empty wheelchair (scene object).
void write_wheelchair_glb(const Wheelchair& chair, const std::filesystem::path& path);
// glb of the CC-BY sweethome3d wheelchair (load_cc_by_wheelchair), one grey mesh.
void write_cc_by_wheelchair_glb(const std::filesystem::path& path);

}  // namespace wheelpose::body
