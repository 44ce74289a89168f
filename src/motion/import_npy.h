#pragma once
// HumanML3D `new_joints` / Text-to-Motion output: float arrays (T, 22, 3) in SMPL-22 joint order,
// metres, +Y up, 20 fps; or (T, 23, 3) with the neck base appended as index 22.

#include <filesystem>

#include "motion/clip.h"
#include "motion/importers.h"

namespace wheelpose::motion {

// Name of each SMPL-22 index (0 pelvis ... 21 right_wrist), plus "neck_base" for index 22.
const std::vector<std::string>& smpl22_joint_names();

PositionClip import_npy(const std::filesystem::path& path, const ImportOptions& options);

}  // namespace wheelpose::motion
