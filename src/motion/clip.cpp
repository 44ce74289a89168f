#include "motion/clip.h"

#include "core/error.h"

namespace wheelpose::motion {

PoseRotations global_rotations(const SkeletalMotion& motion, std::size_t frame) {
  WHEELPOSE_CHECK(frame < motion.local_rotations.size());
  const PoseRotations& local = motion.local_rotations[frame];
  PoseRotations global;
  for (int joint : joints_parent_first()) {
    const int parent = joint_parent(joint);
    global[joint] = parent < 0 ? local[joint] : global[parent] * local[joint];
  }
  return global;
}

Pose forward_kinematics(const SkeletalMotion& motion, std::size_t frame) {
  const PoseRotations global = global_rotations(motion, frame);
  Pose positions;
  for (int joint : joints_parent_first()) {
    const int parent = joint_parent(joint);
    positions[joint] = parent < 0 ? motion.root_positions[frame]
                                  : positions[parent] + global[parent] * motion.rest_offsets[joint];
  }
  return positions;
}

std::vector<Pose> forward_kinematics(const SkeletalMotion& motion) {
  std::vector<Pose> frames(motion.frame_count());
  for (std::size_t f = 0; f < frames.size(); ++f) frames[f] = forward_kinematics(motion, f);
  return frames;
}

}  // namespace wheelpose::motion
