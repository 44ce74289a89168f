#pragma once
// Bringing any source into the WheelPose frame: un-mirror left/right-swapped data (the HumanAct12
// part of HumanML3D, reference §1.5 branch B), turn the body to face +Z at the first frame and
// move the first frame's pelvis over the origin.

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "motion/clip.h"

namespace wheelpose::motion {

enum class Handedness {
  kAuto,      // for sources that may be mirrored: mirrored if the head points backwards
              // relative to the hips' facing; other sources are taken as standard
  kStandard,  // labels match geometry: left joints on the subject's left
  kMirrored,  // left/right geometry is mirrored: reflect it
};

Handedness handedness_from_name(const std::string& name);  // "auto" | "standard" | "mirrored"
std::string handedness_name(Handedness handedness);

// Horizontal unit direction the body faces, from the hips: (left_hip - right_hip) x up.
Eigen::Vector3d hip_facing(const Pose& pose);

// True when the head-forward direction (head_base -> head_top, horizontal part, averaged over
// frames) is opposite to the hips' facing — the signature of mirrored data. Sources whose head
// segment points straight up (no forward lean to judge by) are reported as not mirrored.
bool looks_mirrored(const std::vector<Pose>& frames);

struct OrientationResult {
  bool mirrored = false;
  double yaw_radians = 0;  // rotation about +Y that was applied
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
};

OrientationResult normalize_orientation(std::vector<Pose>& frames, Handedness handedness);

}  // namespace wheelpose::motion
