#pragma once
// Hands on the push rims: for pushing clips, each arm is bent by two-bone IK so that the wrist
// meets the rim of its rear wheel at the point nearest to where the clip put it. The stroke of
// the clip therefore slides the hands along the rims instead of pushing the air.

#include "body/rig.h"
#include "body/wheelchair.h"

namespace wheelpose::body {

// Changes the global rotations of the upper arms and everything below them in `pose` (rig bones
// upperarm_l/_r, lowerarm_l/_r). `rest` are the rest bones; the chair is in the same frame as
// the posed body. Chairs without push rims (power) leave the pose alone. Returns how many hands
// were placed.
int reach_push_rims(const Rig& rig, const BoneFrames& rest, const Wheelchair& chair, RigPose& pose);

// The push-rim circle of one side: centre, unit axis (pointing away from the chair's middle)
// and radius; false when the chair has no rim on that side.
bool push_rim_circle(const Wheelchair& chair, bool left, Eigen::Vector3f& centre,
                     Eigen::Vector3f& axis, float& radius);

}  // namespace wheelpose::body
