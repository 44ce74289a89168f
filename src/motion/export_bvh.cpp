#include "motion/export_bvh.h"

#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "core/atomic_file.h"
#include "core/error.h"
#include "motion/stick_figure.h"

namespace wheelpose::motion {

namespace {

constexpr double kEndSiteLength = 0.05;

// printf("%.6f") is locale-independent only for the "C" locale, which we never change; "-0"
// is folded to "0" so that tiny negative noise doesn't change the bytes.
std::string fixed6(double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.6f", value);
  std::string text(buffer);
  if (text == "-0.000000") text = "0.000000";
  return text;
}

std::string vector_text(const Eigen::Vector3d& v) {
  return fixed6(v.x()) + " " + fixed6(v.y()) + " " + fixed6(v.z());
}

std::vector<int> children_of(int joint) {
  std::vector<int> children;
  for (int j = 0; j < kJointCount; ++j) {
    if (joint_parent(j) == joint) children.push_back(j);
  }
  return children;
}

void write_joint(const SkeletalMotion& motion, int joint, int depth, std::string& out,
                 std::vector<int>& order) {
  const std::string indent(static_cast<std::size_t>(depth) * 2, ' ');
  order.push_back(joint);
  if (joint_parent(joint) < 0) {
    out += "ROOT " + std::string(joint_name(joint)) + "\n{\n";
    out += "  OFFSET 0.000000 0.000000 0.000000\n";
    out += "  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n";
  } else {
    out += indent + "JOINT " + std::string(joint_name(joint)) + "\n" + indent + "{\n";
    out += indent + "  OFFSET " + vector_text(motion.rest_offsets[joint]) + "\n";
    out += indent + "  CHANNELS 3 Zrotation Xrotation Yrotation\n";
  }
  const std::vector<int> children = children_of(joint);
  for (int child : children) write_joint(motion, child, depth + 1, out, order);
  if (children.empty()) {
    // Importers need a bone tail for leaves; continue along the leaf's own bone.
    Eigen::Vector3d direction = motion.rest_offsets[joint];
    if (direction.norm() < 1e-9) direction = rest_direction(joint);
    const Eigen::Vector3d end = direction.normalized() * kEndSiteLength;
    out += indent + "  End Site\n" + indent + "  {\n";
    out += indent + "    OFFSET " + vector_text(end) + "\n" + indent + "  }\n";
  }
  out += indent + "}\n";
}

// Adds whole turns so that the angle is as close as possible to the previous frame's value:
// the rotation is unchanged but curves don't jump by 360° in animation editors.
double unwrap(double angle, double previous) {
  constexpr double kTurn = 2 * std::numbers::pi;
  return angle + kTurn * std::round((previous - angle) / kTurn);
}

}  // namespace

Eigen::Vector3d euler_zxy(const Eigen::Quaterniond& q) {
  // With R = Rz(a)·Rx(b)·Ry(c): R(2,1) = sin b, R(2,0) = -cos b sin c, R(2,2) = cos b cos c,
  // R(0,1) = -sin a cos b, R(1,1) = cos a cos b.
  const Eigen::Matrix3d r = q.normalized().toRotationMatrix();
  const double b = std::asin(std::clamp(r(2, 1), -1.0, 1.0));
  double a = 0;
  double c = 0;
  if (std::abs(r(2, 1)) < 1 - 1e-12) {
    a = std::atan2(-r(0, 1), r(1, 1));
    c = std::atan2(-r(2, 0), r(2, 2));
  } else {
    // Gimbal lock: only a ± c is defined; put it all in a (c = 0 gives R = Rz(a)·Rx(b)).
    a = std::atan2(r(1, 0), r(0, 0));
  }
  return Eigen::Vector3d(a, b, c);
}

std::string bvh_text(const SkeletalMotion& motion) {
  check_exportable(motion, "BVH");
  std::string out = "HIERARCHY\n";
  std::vector<int> order;
  write_joint(motion, kPelvis, 0, out, order);

  char frame_time[64];
  std::snprintf(frame_time, sizeof frame_time, "%.9f", 1.0 / motion.fps);
  out += "MOTION\nFrames: " + std::to_string(motion.frame_count()) + "\n";
  out += "Frame Time: " + std::string(frame_time) + "\n";

  constexpr double kDegrees = 180.0 / std::numbers::pi;
  std::vector<Eigen::Vector3d> previous(kJointCount, Eigen::Vector3d::Zero());
  for (std::size_t f = 0; f < motion.frame_count(); ++f) {
    std::string line = vector_text(motion.root_positions[f]);
    for (int joint : order) {
      Eigen::Vector3d angles = euler_zxy(motion.local_rotations[f][joint]);
      for (int k = 0; k < 3; ++k) angles[k] = unwrap(angles[k], previous[joint][k]);
      previous[joint] = angles;
      line += " " + vector_text(angles * kDegrees);
    }
    out += line + "\n";
  }
  return out;
}

void write_bvh(const SkeletalMotion& motion, const std::filesystem::path& path) {
  write_file_atomic(path, bvh_text(motion));
}

}  // namespace wheelpose::motion
