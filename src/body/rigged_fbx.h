#pragma once
// A person rigged and animated by a seated clip, as binary FBX 7.4 for Blender, Unity and the
// Autodesk FBX SDK: the glb's content (rigged_glb.h) in FBX's terms, written with
// motion/fbx_scene.h like the seated clips' FBX:
//  * a Null "wheelpose_person" holding the rig's 53 bones as LimbNodes at their rest positions
//    (the rest pose has no bone rotations) and one Mesh model per mesh of rigged_parts.h;
//  * each skinned mesh with a Skin deformer, one cluster per bone it uses (MakeHuman's weights,
//    at most four per vertex), and a BindPose at the rest positions; the chair and a walker are
//    unskinned children of the Null;
//  * one lambert material per colour, the static export's;
//  * one animation stack named after the clip: every bone's Euler rotation curve (degrees,
//    unwrapped, in the order that keeps linear interpolation closest to the rotation; see
//    motion/euler_curves.h) and the root bone's translation, one linear key per frame at exact
//    ticks, TimeMode and span the clip's.
// Equal inputs give equal bytes; the file is written whole or not at all.

#include <filesystem>

#include "body/rigged_parts.h"
#include "motion/fbx_node.h"

namespace wheelpose::body {

// The document; throws Error (bad input) for a clip name or mesh name FBX cannot hold, or a
// rate outside FBX time's range.
std::vector<motion::fbx::Node> rigged_person_fbx_document(const PersonAnimation& animation,
                                                          const BodyData& data);

void write_rigged_person_fbx(const PersonAnimation& animation, const BodyData& data,
                             const std::filesystem::path& path);

}  // namespace wheelpose::body
