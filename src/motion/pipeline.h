#pragma once
// The motion pipeline: any PositionClip -> a seated wheelchair-user clip.
//   validate -> orient (un-mirror, face +Z) -> low-pass joint positions -> solve rotations
//   -> seat the legs with rotational noise -> forward kinematics.
// Every parameter lives in MotionOptions, read from the `motion:` section of a YAML config
// (configs/motion.yaml documents each key); the defaults are the paper's.

#include <cstdint>
#include <string>

#include "core/config.h"
#include "motion/clip.h"
#include "motion/clip_checks.h"
#include "motion/orientation.h"
#include "motion/seating.h"

namespace wheelpose::motion {

struct MotionOptions {
  Handedness handedness = Handedness::kAuto;
  bool filter = true;
  int filter_order = 3;
  double filter_cutoff_hz = 5.0;
  bool seat = true;
  SeatingOptions seating;
  ClipLimits limits;
  std::uint64_t seed = 0;

  // Reads the keys of a `motion:` map; unknown keys and bad values name file:line:key.
  static MotionOptions from_config(const ConfigNode& node);
  // Throws Error (bad input) naming the first option outside its range (the ranges from_config
  // enforces); run_motion_pipeline calls it.
  void check() const;
  nlohmann::ordered_json to_json() const;
};

// Throws Error naming the clip when it is broken (see clip_checks.h).
SeatedClip run_motion_pipeline(const PositionClip& clip, const MotionOptions& options);

// Keeps each joint's quaternions in one hemisphere over time (q and -q are the same rotation;
// interpolating exporters need neighbours on the same side).
void make_rotations_continuous(SkeletalMotion& motion);

}  // namespace wheelpose::motion
