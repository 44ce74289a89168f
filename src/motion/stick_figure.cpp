#include "motion/stick_figure.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"

namespace wheelpose::motion {

namespace {

constexpr double kLeafTipLength = 0.06;

[[noreturn]] void reject(const SkeletalMotion& motion, std::string_view format,
                         const std::string& what) {
  throw Error("motion '" + motion.name + "': cannot write " + std::string(format) + ": " + what,
              ErrorKind::kBadInput);
}

bool finite(const Eigen::Vector3d& v) { return v.allFinite(); }

}  // namespace

void check_exportable(const SkeletalMotion& motion, std::string_view format) {
  if (!(std::isfinite(motion.fps) && motion.fps > 0)) {
    reject(motion, format, "fps must be a positive number, got " + std::to_string(motion.fps));
  }
  if (motion.frame_count() == 0) reject(motion, format, "it has no frames");
  if (motion.root_positions.size() != motion.frame_count()) {
    reject(motion, format,
           std::to_string(motion.root_positions.size()) + " root positions for " +
               std::to_string(motion.frame_count()) + " frames of rotations");
  }
  for (int j = 0; j < kJointCount; ++j) {
    if (!finite(motion.rest_offsets[j])) {
      reject(motion, format, "rest offset of '" + std::string(joint_name(j)) + "' is not finite");
    }
  }
  for (std::size_t f = 0; f < motion.frame_count(); ++f) {
    if (!finite(motion.root_positions[f])) {
      reject(motion, format, "frame " + std::to_string(f) + ": root position is not finite");
    }
    for (int j = 0; j < kJointCount; ++j) {
      const Eigen::Quaterniond& q = motion.local_rotations[f][j];
      if (!q.coeffs().allFinite() || std::abs(q.norm() - 1.0) > 1e-3) {
        reject(motion, format,
               "frame " + std::to_string(f) + ": rotation of '" + std::string(joint_name(j)) +
                   "' is not a unit quaternion");
      }
    }
  }
}

Pose rest_pose(const SkeletalMotion& motion, const Eigen::Vector3d& root) {
  Pose pose;
  for (int joint : joints_parent_first()) {
    const int parent = joint_parent(joint);
    pose[joint] = parent < 0 ? root : pose[parent] + motion.rest_offsets[joint];
  }
  return pose;
}

Eigen::Vector3d bind_root_position(const SkeletalMotion& motion) {
  const Pose pose = rest_pose(motion, Eigen::Vector3d::Zero());
  double lowest = 0;
  for (const Eigen::Vector3d& p : pose) lowest = std::min(lowest, p.y());
  return Eigen::Vector3d(0, -lowest, 0);
}

StickMesh build_stick_mesh(const Pose& pose) {
  StickMesh mesh;
  auto add_bone = [&mesh](const Eigen::Vector3d& start, const Eigen::Vector3d& end, int owner) {
    const Eigen::Vector3d axis = end - start;
    const double length = axis.norm();
    if (length < 1e-6) return;
    // The widest point sits a fifth of the way along the bone, like a classic bone glyph.
    const Eigen::Vector3d dir = axis / length;
    const Eigen::Vector3d helper =
        std::abs(dir.y()) < 0.9 ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d u = dir.cross(helper).normalized();
    const Eigen::Vector3d v = dir.cross(u);
    const double radius = std::clamp(0.1 * length, 0.008, 0.03);
    const Eigen::Vector3d middle = start + 0.2 * axis;
    const std::array<Eigen::Vector3d, 4> ring = {middle + radius * u, middle + radius * v,
                                                 middle - radius * u, middle - radius * v};
    auto add_triangle = [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                            const Eigen::Vector3d& c) {
      const Eigen::Vector3d normal = (b - a).cross(c - a).normalized();
      const auto base = static_cast<std::uint32_t>(mesh.positions.size());
      for (const Eigen::Vector3d* p : {&a, &b, &c}) {
        mesh.positions.push_back(p->cast<float>());
        mesh.normals.push_back(normal.cast<float>());
        mesh.vertex_joint.push_back(owner);
      }
      mesh.triangles.push_back({base, base + 1, base + 2});
    };
    for (int i = 0; i < 4; ++i) {
      const Eigen::Vector3d& a = ring[i];
      const Eigen::Vector3d& b = ring[(i + 1) % 4];
      // Counter-clockwise seen from outside: u, v, -u, -v turn positively about dir.
      add_triangle(start, b, a);
      add_triangle(end, a, b);
    }
  };
  std::array<bool, kJointCount> has_child{};
  for (int joint = 0; joint < kJointCount; ++joint) {
    const int parent = joint_parent(joint);
    if (parent < 0) continue;
    has_child[parent] = true;
    add_bone(pose[parent], pose[joint], parent);
  }
  // Leaves (head top, hands, feet) get a short tip of their own, so every joint moves some
  // geometry (Assimp refuses bones without weights) and the hands and feet show their twist.
  for (int joint = 0; joint < kJointCount; ++joint) {
    const int parent = joint_parent(joint);
    if (has_child[joint] || parent < 0) continue;
    Eigen::Vector3d direction = pose[joint] - pose[parent];
    if (direction.norm() < 1e-9) direction = rest_direction(joint);
    add_bone(pose[joint], pose[joint] + kLeafTipLength * direction.normalized(), joint);
  }
  return mesh;
}

}  // namespace wheelpose::motion
