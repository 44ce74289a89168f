#pragma once
// FBX 7.4 export of a SkeletalMotion, binary (the default: Blender, Unity and the Autodesk FBX
// SDK read it) or ASCII, both from one document (fbx_document, built with fbx_scene.h) so they
// say the same thing. The
// scene is the glb's (export_gltf.h): a "wheelpose_root" Null holding the 23 joints as LimbNode
// models with their rest offsets and the skinned "stick_figure" mesh, plus one animation stack
// named after the motion with
//  * key times exact to the FBX tick: frame · 46186158000 / fps in integers (fbx_time.h);
//  * the stack's Local/Reference Start/Stop and GlobalSettings' TimeSpanStart/Stop equal to the
//    clip's first and last frame, TimeMode the clip's rate (custom rates: 14 with
//    CustomFrameRate);
//  * linear interpolation on every curve (KeyAttrFlags 24836, the FBX SDK's value for linear
//    keys with auto tangents), one key per frame;
//  * per joint Euler curves in degrees that never jump across ±180° between keys, in the
//    rotation order (RotationOrder, RotationActive) that keeps them closest to the rotation
//    between keys (euler_curves.h); pelvis translation curves in metres.
// Units are metres (UnitScaleFactor 100 cm), +Y up, the figure faces +Z.

#include <filesystem>
#include <vector>

#include "motion/clip.h"
#include "motion/fbx_scene.h"

namespace wheelpose::motion {

using FbxEncoding = fbx::Encoding;
inline constexpr std::uint32_t kFbxVersion = fbx::kVersion;

// Throws Error (bad input) naming the motion when FBX cannot hold it: the checks of
// check_exportable (no frames, fps not positive or NaN, ...), a rate outside fbx_time.h's range,
// or a motion name with control characters, quotes or "::" (FBX's class separator).
std::vector<fbx::Node> fbx_document(const SkeletalMotion& motion, FbxEncoding encoding);

// The file is written whole or not at all.
void write_fbx(const SkeletalMotion& motion, const std::filesystem::path& path);
void write_fbx_ascii(const SkeletalMotion& motion, const std::filesystem::path& path);

}  // namespace wheelpose::motion
