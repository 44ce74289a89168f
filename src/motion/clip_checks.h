#pragma once
// Rejecting broken clips before they reach the pipeline: non-finite values, too few frames for
// the filter, bones that collapse to nothing or stretch impossibly between frames.

#include <string>

#include "motion/clip.h"

namespace wheelpose::motion {

struct ClipLimits {
  int min_frames = 13;             // the filter needs more frames than its padding (12)
  double min_bone_length = 0.005;  // metres; shorter = collapsed joints
  double max_bone_length = 1.0;    // metres; longer = exploding data
  double max_length_change = 0.5;  // fraction of the median length a bone may gain or lose
  double length_change_slack = 0.03;  // metres added to that tolerance for noisy keypoints
};

// Throws Error "<source>: <reason>" naming the frame, joint or bone that fails.
void validate_position_clip(const PositionClip& clip, const ClipLimits& limits);

}  // namespace wheelpose::motion
