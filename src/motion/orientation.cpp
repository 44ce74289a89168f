#include "motion/orientation.h"

#include <cmath>

#include "core/error.h"

namespace wheelpose::motion {

Handedness handedness_from_name(const std::string& name) {
  if (name == "auto") return Handedness::kAuto;
  if (name == "standard") return Handedness::kStandard;
  if (name == "mirrored") return Handedness::kMirrored;
  throw Error("handedness '" + name + "' is not one of: auto, standard, mirrored");
}

std::string handedness_name(Handedness handedness) {
  switch (handedness) {
    case Handedness::kAuto:
      return "auto";
    case Handedness::kStandard:
      return "standard";
    case Handedness::kMirrored:
      return "mirrored";
  }
  return "auto";
}

Eigen::Vector3d hip_facing(const Pose& pose) {
  Eigen::Vector3d facing = (pose[kLeftHip] - pose[kRightHip]).cross(Eigen::Vector3d::UnitY());
  facing.y() = 0;
  const double norm = facing.norm();
  return norm > 1e-9 ? Eigen::Vector3d(facing / norm) : Eigen::Vector3d::UnitZ();
}

bool looks_mirrored(const std::vector<Pose>& frames) {
  double agreement = 0, head_forward = 0, head_length = 0;
  for (const Pose& pose : frames) {
    const Eigen::Vector3d head = pose[kHeadTop] - pose[kHeadBase];
    const Eigen::Vector3d facing = hip_facing(pose);
    agreement += head.dot(facing);
    head_forward += std::abs(head.dot(facing));
    head_length += head.norm();
  }
  // Only trust the head when it leans clearly forward or backward (SMPL's head joint sits in
  // front of its neck joint); an upright head segment says nothing about handedness.
  return head_forward > 0.1 * head_length && agreement < 0;
}

OrientationResult normalize_orientation(std::vector<Pose>& frames, Handedness handedness) {
  OrientationResult result;
  if (frames.empty()) return result;
  result.mirrored = handedness == Handedness::kMirrored ||
                    (handedness == Handedness::kAuto && looks_mirrored(frames));
  if (result.mirrored) {
    for (Pose& pose : frames) {
      for (Eigen::Vector3d& p : pose) p.x() = -p.x();
    }
  }
  const Eigen::Vector3d facing = hip_facing(frames.front());
  result.yaw_radians = -std::atan2(facing.x(), facing.z());
  const Eigen::AngleAxisd yaw(result.yaw_radians, Eigen::Vector3d::UnitY());
  const Eigen::Vector3d pelvis = yaw * frames.front()[kPelvis];
  result.translation = Eigen::Vector3d(-pelvis.x(), 0, -pelvis.z());
  for (Pose& pose : frames) {
    for (Eigen::Vector3d& p : pose) p = yaw * p + result.translation;
  }
  return result;
}

}  // namespace wheelpose::motion
