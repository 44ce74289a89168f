// Procedural cane, forearm crutches and walker placed at the posed hands.

#include "body/mobility_aid.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace wheelpose::body {
namespace {

using Eigen::Vector3f;

constexpr int kShaft = 0, kGrip = 1;

// The grip a little past the wrist along the forearm, the forearm direction, and the tip where a
// shaft of `length` from the grip toward a floor point outside the hand reaches (shortened if
// it would go below the floor).
struct HandHold {
  Vector3f grip, forearm, tip;
};

HandHold hold(const Vector3f& elbow, const Vector3f& wrist, float outward, float length) {
  HandHold h;
  h.forearm = (wrist - elbow).normalized();
  h.grip = wrist + 0.07f * h.forearm;
  const Vector3f target(h.grip.x() + outward * 0.12f, 0.0f, h.grip.z() + 0.06f);
  Vector3f dir = target - h.grip;
  if (dir.squaredNorm() < 1e-6f) dir = -Vector3f::UnitY();
  dir.normalize();
  float reach = length;
  if (dir.y() < -1e-3f) reach = std::min(reach, h.grip.y() / -dir.y());
  h.tip = h.grip + reach * dir;
  return h;
}

// Horizontal direction for handles: the forearm's, or forward.
Vector3f handle_direction(const Vector3f& forearm) {
  Vector3f d(forearm.x(), 0, forearm.z());
  return d.squaredNorm() > 1e-4f ? d.normalized() : Vector3f::UnitZ();
}

void add_cane(MobilityAid& aid, const HandHold& h, const std::string& side) {
  const Vector3f handle = handle_direction(h.forearm);
  aid.parts.push_back(make_tube("cane_shaft" + side, h.grip, h.tip, 0.011f, kShaft));
  aid.parts.push_back(
      make_tube("cane_handle" + side, h.grip - 0.04f * handle, h.grip + 0.08f * handle, 0.014f, kGrip));
  const Vector3f down = (h.tip - h.grip).normalized();
  aid.parts.push_back(make_tube("cane_tip" + side, h.tip - 0.03f * down, h.tip, 0.016f, kGrip));
}

void add_crutch(MobilityAid& aid, const HandHold& h, const Vector3f& elbow, const std::string& side) {
  add_cane(aid, h, side);
  // The cuff holds the forearm a little below the elbow.
  const Vector3f cuff = elbow + 0.3f * (h.grip - elbow);
  aid.parts.push_back(make_tube("crutch_arm" + side, h.grip, cuff, 0.009f, kShaft));
  const Vector3f along = (h.grip - elbow).normalized();
  aid.parts.push_back(
      make_tube("crutch_cuff" + side, cuff - 0.03f * along, cuff + 0.03f * along, 0.045f, kGrip));
}

void add_walker(MobilityAid& aid, const AidAnchors& a, RandomStream& rng) {
  const float width = static_cast<float>(rng.uniform(0.5, 0.6));
  const float depth = static_cast<float>(rng.uniform(0.35, 0.45));
  const float height = static_cast<float>(rng.uniform(0.78, 0.9));
  const Vector3f knees = (a.left_knee + a.right_knee) / 2;
  const float back = std::max(a.left_knee.z(), a.right_knee.z()) + 0.12f;
  const float front = back + depth, x = knees.x(), hw = width / 2;
  const Vector3f corners[4] = {{x - hw, 0, back}, {x + hw, 0, back}, {x - hw, 0, front}, {x + hw, 0, front}};
  for (int i = 0; i < 4; ++i) {
    const Vector3f top = corners[i] + Vector3f(0, height, 0);
    aid.parts.push_back(make_tube("walker_leg_" + std::to_string(i), corners[i], top, 0.013f, kShaft));
    aid.parts.push_back(make_tube("walker_foot_" + std::to_string(i), corners[i],
                                  corners[i] + Vector3f(0, 0.03f, 0), 0.018f, kGrip));
  }
  const Vector3f up(0, height, 0);
  aid.parts.push_back(make_tube("walker_side_left", corners[0] + up, corners[2] + up, 0.013f, kShaft));
  aid.parts.push_back(make_tube("walker_side_right", corners[1] + up, corners[3] + up, 0.013f, kShaft));
  aid.parts.push_back(make_tube("walker_front", corners[2] + up, corners[3] + up, 0.013f, kShaft));
  aid.parts.push_back(make_tube("walker_brace", corners[2] + 0.45f * up, corners[3] + 0.45f * up, 0.01f, kShaft));
  for (int i = 0; i < 2; ++i) {
    const Vector3f grip = corners[i] + up + Vector3f(0, 0.01f, 0.02f);
    aid.parts.push_back(make_tube("walker_grip_" + std::to_string(i), grip,
                                  grip + Vector3f(0, 0, 0.12f), 0.018f, kGrip));
  }
}

}  // namespace

const char* mobility_aid_name(MobilityAidType type) {
  switch (type) {
    case MobilityAidType::kNone: return "none";
    case MobilityAidType::kCane: return "cane";
    case MobilityAidType::kCrutches: return "crutches";
    case MobilityAidType::kWalker: return "walker";
  }
  return "none";
}

MobilityAidType mobility_aid_from_name(const std::string& name) {
  for (MobilityAidType t : {MobilityAidType::kNone, MobilityAidType::kCane,
                            MobilityAidType::kCrutches, MobilityAidType::kWalker}) {
    if (name == mobility_aid_name(t)) return t;
  }
  throw Error("mobility aid '" + name + "': expected none, cane, crutches or walker");
}

MobilityAid make_mobility_aid(MobilityAidType type, const AidAnchors& a, RandomStream& rng) {
  MobilityAid aid;
  const float shade = static_cast<float>(rng.uniform(0.25, 0.75));
  const bool coloured = rng.bernoulli(0.4);
  aid.colours = {coloured ? Vector3f(static_cast<float>(rng.uniform(0.05, 0.8)),
                                     static_cast<float>(rng.uniform(0.05, 0.8)),
                                     static_cast<float>(rng.uniform(0.05, 0.8)))
                          : Vector3f::Constant(shade),
                 Vector3f::Constant(static_cast<float>(rng.uniform(0.02, 0.1)))};
  const float length = static_cast<float>(rng.uniform(0.8, 0.95));
  // The person's left is +X, so outward is +X for the left hand and −X for the right.
  switch (type) {
    case MobilityAidType::kNone:
      break;
    case MobilityAidType::kCane:
      if (a.right_hand) {
        add_cane(aid, hold(a.right_elbow, a.right_wrist, -1, length), "_right");
      } else if (a.left_hand) {
        add_cane(aid, hold(a.left_elbow, a.left_wrist, 1, length), "_left");
      }
      break;
    case MobilityAidType::kCrutches:
      if (a.left_hand) add_crutch(aid, hold(a.left_elbow, a.left_wrist, 1, length), a.left_elbow, "_left");
      if (a.right_hand)
        add_crutch(aid, hold(a.right_elbow, a.right_wrist, -1, length), a.right_elbow, "_right");
      break;
    case MobilityAidType::kWalker:
      add_walker(aid, a, rng);
      break;
  }
  aid.type = aid.parts.empty() ? MobilityAidType::kNone : type;
  return aid;
}

}  // namespace wheelpose::body
