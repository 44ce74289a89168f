#pragma once
// Mobility aids held by a seated person: a cane in one hand, a forearm crutch in each hand, or
// a walker standing in front of the knees. Built from primitives around the posed body (its
// coordinates: floor at y = 0, facing +Z), so they follow any pose and body size.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "body/wheelchair.h"
#include "core/random.h"

namespace wheelpose::body {

enum class MobilityAidType { kNone, kCane, kCrutches, kWalker };
const char* mobility_aid_name(MobilityAidType type);
MobilityAidType mobility_aid_from_name(const std::string& name);  // throws Error

struct MobilityAid {
  MobilityAidType type = MobilityAidType::kNone;
  std::vector<Primitive> parts;           // material 0 = shaft/frame, 1 = grips, cuffs, tips
  std::vector<Eigen::Vector3f> colours;   // per material
};

// Where the hands and knees are: COCO-17 points of the posed body and which are present.
struct AidAnchors {
  Eigen::Vector3f left_elbow, right_elbow, left_wrist, right_wrist, left_knee, right_knee;
  bool left_hand = true, right_hand = true;
};

// The aid for these anchors; a hand-held aid needs a hand (a cane takes the right one unless it
// is missing; crutches take every hand present). No hand → no aid.
MobilityAid make_mobility_aid(MobilityAidType type, const AidAnchors& anchors, RandomStream& rng);

}  // namespace wheelpose::body
