// Two-bone IK of the arms onto the push rims.

#include "body/rim_reach.h"

#include <algorithm>
#include <cmath>

namespace wheelpose::body {
namespace {

using Eigen::Quaternionf;
using Eigen::Vector3f;

// Bones below `root` (itself included), in the rig's parent-first order.
std::vector<bool> subtree(const Rig& rig, int root) {
  std::vector<bool> in(rig.bones.size(), false);
  for (std::size_t b = 0; b < rig.bones.size(); ++b) {
    const int p = rig.bones[b].parent;
    in[b] = static_cast<int>(b) == root || (p >= 0 && in[static_cast<std::size_t>(p)]);
  }
  return in;
}

void rotate_subtree(const std::vector<bool>& in, const Quaternionf& q, RigPose& pose) {
  for (std::size_t b = 0; b < in.size(); ++b)
    if (in[b]) pose.rotation[b] = (q * pose.rotation[b]).normalized();
}

}  // namespace

bool push_rim_circle(const Wheelchair& chair, bool left, Vector3f& centre, Vector3f& axis,
                     float& radius) {
  std::vector<Vector3f> points;
  for (const Primitive& p : chair.parts) {
    if (p.part.rfind("push_rim", 0) == 0 && (p.centre.x() > 0) == left) points.push_back(p.centre);
  }
  if (points.size() < 3) return false;
  centre = Vector3f::Zero();
  for (const auto& p : points) centre += p;
  centre /= static_cast<float>(points.size());
  const std::size_t n = points.size();
  axis = (points[n / 3] - points[0]).cross(points[2 * n / 3] - points[0]).normalized();
  if ((axis.x() > 0) != left) axis = -axis;  // outward, away from the seat
  radius = 0;
  for (const auto& p : points) radius += (p - centre).norm();
  radius /= static_cast<float>(n);
  return true;
}

int reach_push_rims(const Rig& rig, const BoneFrames& rest, const Wheelchair& chair, RigPose& pose) {
  int placed = 0;
  for (bool left : {true, false}) {
    const char* side = left ? "_l" : "_r";
    const int upper = rig.bone(std::string("upperarm") + side);
    const int lower = rig.bone(std::string("lowerarm") + side);
    const int hand = rig.bone(std::string("hand") + side);
    Vector3f centre, axis;
    float radius = 0;
    if (upper < 0 || lower < 0 || hand < 0 || !push_rim_circle(chair, left, centre, axis, radius))
      continue;
    const BoneFrames posed = pose_bones(rig, rest, pose);
    const Vector3f s = posed.head[upper], e = posed.head[lower], w = posed.head[hand];
    // The rim point nearest to where the clip put the wrist; the wrist sits just outside it.
    Vector3f in_plane = w - centre;
    in_plane -= in_plane.dot(axis) * axis;
    if (in_plane.squaredNorm() < 1e-8f) in_plane = Vector3f::UnitY();
    const Vector3f target = centre + radius * in_plane.normalized() + 0.04f * axis;

    const float l1 = (e - s).norm(), l2 = (w - e).norm();
    Vector3f to_target = target - s;
    const float reach = std::clamp(to_target.norm(), std::abs(l1 - l2) + 1e-4f, l1 + l2 - 1e-4f);
    to_target.normalize();
    // Keep the elbow on the side it was (the pole), else outward and back.
    Vector3f pole = (e - s) - (e - s).dot(to_target) * to_target;
    if (pole.squaredNorm() < 1e-8f) pole = axis - Vector3f::UnitZ();
    pole = (pole - pole.dot(to_target) * to_target).normalized();
    const float cos_a = std::clamp((l1 * l1 + reach * reach - l2 * l2) / (2 * l1 * reach), -1.0f, 1.0f);
    const Vector3f elbow = s + l1 * (cos_a * to_target + std::sqrt(1 - cos_a * cos_a) * pole);
    const Vector3f wrist = s + reach * to_target;

    const Quaternionf q1 = Quaternionf::FromTwoVectors(e - s, elbow - s);
    rotate_subtree(subtree(rig, upper), q1, pose);
    const Quaternionf q2 = Quaternionf::FromTwoVectors(q1 * (w - e), wrist - elbow);
    rotate_subtree(subtree(rig, lower), q2, pose);
    ++placed;
  }
  return placed;
}

}  // namespace wheelpose::body
