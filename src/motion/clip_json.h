#pragma once
// The seated-clip JSON file (`<name>.json`), the seam between the motion stage and the review
// app, the body stage and scene generation. Layout (format "wheelpose.seated_clip", version 1):
//   name, fps, frame_count, frame {units, up, facing, left},
//   skeleton {joints [names], parents [index or -1], rest_offsets [[x,y,z] per joint]},
//   root_positions [[x,y,z] per frame],
//   local_rotations [[[w,x,y,z] per joint] per frame],
//   positions [[[x,y,z] per joint] per frame], provenance {...}.
// Numbers are rounded to 1e-6 m and 1e-7 for quaternion components, so files are compact and
// identical for identical inputs.

#include <filesystem>
#include <string>

#include "motion/clip.h"

namespace wheelpose::motion {

nlohmann::ordered_json seated_clip_to_json(const SeatedClip& clip);
std::string seated_clip_json_text(const SeatedClip& clip);
void write_seated_clip_json(const SeatedClip& clip, const std::filesystem::path& path);

// Reads a file written by write_seated_clip_json; throws Error naming the file and field.
SeatedClip read_seated_clip_json(const std::filesystem::path& path);

}  // namespace wheelpose::motion
