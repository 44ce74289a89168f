#pragma once
// Motion importers: read one motion file (HumanML3D .npy, BVH, CSV/JSON keypoints) into 23-joint
// positions. Formats are chosen by name or by file extension from one table (importers.cpp).

#include <filesystem>
#include <string>
#include <vector>

#include "motion/clip.h"

namespace wheelpose::motion {

struct ImportOptions {
  std::string format;     // "" = choose by file extension; else "npy", "bvh", "csv", "json"
  double fps = 0;         // 0 = the format's own/default rate (npy: 20 fps, HumanML3D; bvh: from
                          // Frame Time; csv/json: from the file if it says, else 30)
  std::string mapping;    // joint-name mapping: bvh: "cmu" (default; built in); csv/json:
                          // "wheelpose23" (default) or "blazepose33"
  double unit_scale = 0;  // metres per source unit; 0 = the mapping's default
};

// Reads one motion file into 23-joint positions (metres, +Y up; facing left as in the source —
// the pipeline normalises facing and detects mirrored data later). Throws wheelpose::Error naming
// the file and the problem.
PositionClip import_motion(const std::filesystem::path& path, const ImportOptions& options);

std::vector<std::string> importer_formats();  // {"npy","bvh","csv","json"}

}  // namespace wheelpose::motion
