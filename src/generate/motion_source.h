#pragma once
// The seated clips people play: the built-in motion library run through the motion pipeline
// (default), or a folder of seated-clip JSON files from `wheelpose motion`, optionally only the
// clips a review ranking keeps (`wheelpose review filter` → ranking.json, its "kept" list).

#include <filesystem>
#include <vector>

#include "motion/clip.h"

namespace wheelpose::generate {

struct MotionSource {
  std::filesystem::path folder;      // empty = built-in library
  std::filesystem::path clips_from;  // empty = every clip
};

// Clips in a stable order (library order, or file name order). Throws Error naming the file for
// unreadable clips, a ranking that names a clip the source lacks, or an empty selection.
std::vector<motion::SeatedClip> load_motion_clips(const MotionSource& source);

}  // namespace wheelpose::generate
