#pragma once
// Biovision Hierarchy (BVH) export of a SkeletalMotion, for Blender, MotionBuilder and Unity.
//
// HIERARCHY: the 23 joints by name, offsets in metres in the parent's frame (+Y up, facing +Z);
// the pelvis is the ROOT with channels "Xposition Yposition Zposition Zrotation Xrotation
// Yrotation", every other joint has "Zrotation Xrotation Yrotation"; leaves (head_top, wrists,
// toes) end in an End Site 5 cm along their bone. MOTION: one line per frame, Frame Time = 1/fps,
// Euler angles in degrees with R = Rz·Rx·Ry (the order the channels are listed), every number
// printed with 6 decimals so the text is byte-identical everywhere.

#include <filesystem>
#include <string>

#include "motion/clip.h"

namespace wheelpose::motion {

std::string bvh_text(const SkeletalMotion& motion);
void write_bvh(const SkeletalMotion& motion, const std::filesystem::path& path);

// Angles (radians) (z, x, y) with q = Rz(z)·Rx(x)·Ry(y); x in [-pi/2, pi/2]. Exposed for tests.
Eigen::Vector3d euler_zxy(const Eigen::Quaterniond& q);

}  // namespace wheelpose::motion
