#pragma once
// A person rigged and animated by a seated clip, as glb for Blender, Unity and three.js:
//  * the rig's 53 bones as joint nodes under the node "wheelpose_person", each at its rest
//    position (translation only: the rest pose has no bone rotations);
//  * the meshes of rigged_parts.h: skinned ones are scene roots, as glTF advises (their parents'
//    transforms would not apply), and move through the joints; the chair (and a walker) sit
//    unskinned under the root;
//  * one animation named after the clip: every joint's rotation and the root joint's translation
//    at every frame (frame / fps seconds), linear, quaternions kept in one hemisphere.
// Written by our own glTF writer (motion::GlbBuilder), not Assimp's, which welds skinned
// vertices and loses weights. Equal inputs give equal bytes.

#include <filesystem>

#include "body/rigged_parts.h"

namespace wheelpose::body {

void write_rigged_person_glb(const PersonAnimation& animation, const BodyData& data,
                             const std::filesystem::path& path);

}  // namespace wheelpose::body
