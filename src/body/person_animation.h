#pragma once
// A person played through a whole seated clip: the rig pose build_person gives at every frame,
// so an exported animation shows exactly the bodies the generator renders.

#include <string>
#include <vector>

#include "body/person.h"
#include "motion/clip.h"

namespace wheelpose::body {

struct PersonAnimation {
  std::string name;  // the clip's
  double fps = 30;
  Person person;                // at the clip's first frame: rest mesh, chair, garments, aid
  std::vector<RigPose> frames;  // Person::pose at every clip frame (floor shift included)
};

// Builds `spec` at every frame of `clip` (spec.pose is replaced). Throws Error (bad input) for a
// clip that cannot be exported: no frames, a rate that is not a positive number, non-finite
// values.
PersonAnimation animate_person(const BodyData& data, PersonSpec spec,
                               const motion::SkeletalMotion& clip);

}  // namespace wheelpose::body
