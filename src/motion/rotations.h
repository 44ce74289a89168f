#pragma once
// Joint positions -> joint rotations relative to the parent (paper "Pose Modification and
// Conversion"). Single-child joints turn by the shortest arc from where the parent carries the
// bone to where the data puts it, so the twist about a limb's own axis follows the parent (the
// paper's rule for upper arms and forearms). The pelvis and the neck base, which carry three
// bones each, get a full frame from two of them (hips line + spine, clavicles line + neck).
// Rest offsets come from the clip itself (mean bone lengths and mean local offsets), so forward
// kinematics reproduces the positions up to the clip's own bone-length variation.

#include <string>
#include <vector>

#include "motion/clip.h"

namespace wheelpose::motion {

SkeletalMotion solve_rotations(const std::vector<Pose>& frames, double fps, const std::string& name);

// Orthonormal frame whose +X is along `x_axis` and whose +Y is as close as possible to `up`;
// the identity for x_axis = +X, up = +Y.
Eigen::Quaterniond frame_from_axes(const Eigen::Vector3d& x_axis, const Eigen::Vector3d& up);

}  // namespace wheelpose::motion
