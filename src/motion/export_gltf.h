#pragma once
// glTF 2.0 binary (.glb) export of a SkeletalMotion, for Blender, Unity and three.js
// (export_fbx.h writes the same scene as FBX). The file holds:
//  * a node hierarchy of the 23 joints named as in skeleton.h ("pelvis", "left_hip", ...), each
//    node translated by its rest offset from its parent; the pelvis sits above the origin so the
//    T-pose stands on the floor;
//  * a skinned stick figure ("stick_figure": one slim octahedron per bone, bound rigidly to the
//    bone's parent joint) so that viewers draw the motion;
//  * one animation named after the motion: the pelvis translation and every joint's local
//    rotation at every frame, keyed at frame / fps seconds.
// Units are metres, +Y up, the figure faces +Z (glTF's own convention, so Blender shows it
// standing on its floor facing −Y, i.e. towards the default front view).

#include <filesystem>

#include "motion/clip.h"

namespace wheelpose::motion {

void write_glb(const SkeletalMotion& motion, const std::filesystem::path& path);

}  // namespace wheelpose::motion
