#pragma once
// Anatomical plausibility of joint positions: joint angles beyond normal human range of motion,
// bones that change length, and arms passing through the torso or head. Usable on any clip on
// the 23-joint skeleton (library motions, imported and seated clips).

#include <string>
#include <vector>

#include "motion/clip.h"

namespace wheelpose::motion {

// Joint-angle measures of one pose (degrees), in the conventions of data/motions/README.md.
struct PoseAngles {
  double elbow_flexion[2];       // [left, right]; 0 = straight
  double arm_extension[2];       // how far the upper arm points behind the frontal plane
  double arm_adduction[2];       // how far it points across the body's midline
  double humeral_rotation[2];    // internal positive; NaN where undefined (straight elbow)
  double clavicle_elevation[2];  // shoulder joint above (+) / below (-) the neck base
  double neck_flexion;           // head axis forward (+) / back (-) of the thorax axis
  double neck_lateral;           // head axis tilted to the left (+)
  double trunk_flexion;          // spine->neck_base forward of the pelvis axis
  double trunk_lateral;          // ... tilted to the left (+)
  double trunk_twist;            // shoulder line turned left (+) of the hip line
};
PoseAngles measure_pose_angles(const Pose& pose);

// Human-readable problems, one per rule and joint, each naming the first offending frame and how
// many frames break the rule. Empty when the clip is plausible.
std::vector<std::string> plausibility_problems(const std::vector<Pose>& frames);

}  // namespace wheelpose::motion
