#include "motion/rotations.h"

#include "core/error.h"

namespace wheelpose::motion {

namespace {

// The joints that carry several bones, with the child pair that defines their frame.
bool is_branch_joint(int joint) { return joint == kPelvis || joint == kNeckBase; }

// Motion capture rigs move these children independently (CMU's lower back, collars and lower
// neck rotate on their own), so a fixed rest offset cannot place all three. Each frame is chosen
// to carry the upper body exactly: the pelvis's +Y runs exactly along the spine (the hips, which
// seating replaces, absorb the difference); the neck base's +X runs exactly along the clavicle
// line, so both arms are exact (the head base absorbs the difference).
Eigen::Quaterniond branch_frame(const Pose& pose, int joint) {
  if (joint == kPelvis) {
    const Eigen::Vector3d up = (pose[kSpine] - pose[kPelvis]).normalized();
    const Eigen::Vector3d side = pose[kLeftHip] - pose[kRightHip];
    return frame_from_axes(side - side.dot(up) * up, up);
  }
  return frame_from_axes(pose[kLeftClavicle] - pose[kRightClavicle],
                         pose[kHeadBase] - pose[kNeckBase]);
}

// The single child of a non-branch joint, or -1 for leaves.
int only_child(int joint) {
  for (int j = 0; j < kJointCount; ++j) {
    if (joint_parent(j) == joint) return j;
  }
  return -1;
}

}  // namespace

Eigen::Quaterniond frame_from_axes(const Eigen::Vector3d& x_axis, const Eigen::Vector3d& up) {
  const Eigen::Vector3d x = x_axis.normalized();
  const Eigen::Vector3d z = x.cross(up).normalized();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d basis;
  basis << x, y, z;
  return Eigen::Quaterniond(basis).normalized();
}

SkeletalMotion solve_rotations(const std::vector<Pose>& frames, double fps,
                               const std::string& name) {
  WHEELPOSE_CHECK(!frames.empty());
  SkeletalMotion motion;
  motion.name = name;
  motion.fps = fps;
  const double inverse_count = 1.0 / static_cast<double>(frames.size());

  // Rest offsets: children of branch joints keep their mean offset in the branch frame; every
  // other bone points along its T-pose direction with its mean length.
  motion.rest_offsets.fill(Eigen::Vector3d::Zero());
  for (int joint = 0; joint < kJointCount; ++joint) {
    const int parent = joint_parent(joint);
    if (parent < 0) continue;
    if (is_branch_joint(parent)) {
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      for (const Pose& pose : frames) {
        sum += branch_frame(pose, parent).conjugate() * (pose[joint] - pose[parent]);
      }
      motion.rest_offsets[joint] = sum * inverse_count;
    } else {
      double length = 0;
      for (const Pose& pose : frames) length += (pose[joint] - pose[parent]).norm();
      motion.rest_offsets[joint] = rest_direction(joint) * (length * inverse_count);
    }
  }

  const auto& order = joints_parent_first();
  motion.root_positions.resize(frames.size());
  motion.local_rotations.resize(frames.size());
  for (std::size_t f = 0; f < frames.size(); ++f) {
    const Pose& pose = frames[f];
    PoseRotations global;
    PoseRotations& local = motion.local_rotations[f];
    for (int joint : order) {
      const int parent = joint_parent(joint);
      const Eigen::Quaterniond parent_global =
          parent < 0 ? Eigen::Quaterniond::Identity() : global[parent];
      if (is_branch_joint(joint)) {
        global[joint] = branch_frame(pose, joint);
      } else if (const int child = only_child(joint); child >= 0) {
        const Eigen::Vector3d carried = parent_global * motion.rest_offsets[child];
        const Eigen::Vector3d actual = pose[child] - pose[joint];
        global[joint] = Eigen::Quaterniond::FromTwoVectors(carried, actual) * parent_global;
      } else {
        global[joint] = parent_global;  // leaves carry no bone
      }
      global[joint].normalize();
      local[joint] = (parent_global.conjugate() * global[joint]).normalized();
    }
    motion.root_positions[f] = pose[kPelvis];
  }
  return motion;
}

}  // namespace wheelpose::motion
