#pragma once
// 3D keypoint sequences in CSV or JSON with a named joint layout ("wheelpose23": our own joint
// names; "blazepose33": MediaPipe Pose world landmarks). Formats are documented in docs/commands/motion.md,
// section "Motion import"; in short:
//   CSV long form:  header `frame,joint,x,y,z`, one row per frame and joint;
//   CSV wide form:  header `frame,<joint>_x,<joint>_y,<joint>_z,...`, one row per frame;
//   both may start with a comment line `# fps: 30`; frame numbers must be consecutive.
//   JSON: {"fps": 30, "joints": [names...], "frames": [[[x,y,z], ...], ...]}.

#include <filesystem>
#include <string>
#include <vector>

#include "motion/clip.h"
#include "motion/import_mapping.h"
#include "motion/importers.h"

namespace wheelpose::motion {

// Built-in keypoint layouts: "wheelpose23" (default) and "blazepose33".
const std::vector<ImportMapping>& keypoint_mappings();

PositionClip import_keypoints_csv(const std::filesystem::path& path, const ImportOptions& options);
PositionClip import_keypoints_json(const std::filesystem::path& path, const ImportOptions& options);

}  // namespace wheelpose::motion
