#pragma once
// A person rigged and animated by a seated clip, as glb for Blender, Unity and three.js:
//  * the rig's 53 bones as joint nodes under the node "wheelpose_person", each at its rest
//    position (translation only: the rest pose has no bone rotations);
//  * the body, clothes and hair in their rest shape, skinned to those joints (the body with
//    MakeHuman's weights, a proxy vertex with its reference vertices' weights blended), at most
//    four per vertex, summing to 1; skinned mesh nodes are scene roots, as glTF advises (their
//    parents' transforms would not apply), and move through the joints;
//  * the wheelchair unskinned under the root: the body stage keeps it still while the clip turns
//    the pelvis, so it belongs to the person, not to a bone; a walker likewise;
//  * a cane or crutch skinned rigidly to the hand bone holding it, placed as at the first frame;
//  * one animation named after the clip: every joint's rotation and the root joint's translation
//    at every frame (frame / fps seconds), linear, quaternions kept in one hemisphere.
// Colours are the static export's (glb_parts.h). Written by our own glTF writer
// (motion::GlbBuilder), not Assimp's, which welds skinned vertices and loses weights. Equal
// inputs give equal bytes.

#include <filesystem>

#include "body/person_animation.h"

namespace wheelpose::body {

void write_rigged_person_glb(const PersonAnimation& animation, const BodyData& data,
                             const std::filesystem::path& path);

}  // namespace wheelpose::body
