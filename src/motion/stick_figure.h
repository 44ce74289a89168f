#pragma once
// Helpers shared by the motion exporters: input checks and the stick-figure mesh that stands in
// for a body in the glTF/FBX files (so a viewer shows something skinned to the skeleton).

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string_view>
#include <vector>

#include "motion/clip.h"

namespace wheelpose::motion {

// Throws Error (kBadInput) naming the motion and `format` when the motion cannot be exported:
// no frames, fps not positive, per-frame arrays of different lengths, non-finite values.
void check_exportable(const SkeletalMotion& motion, std::string_view format);

// Joint positions of the rest (T-)pose with the pelvis at `root`.
Pose rest_pose(const SkeletalMotion& motion, const Eigen::Vector3d& root);

// Where exporters put the pelvis in the bind pose: above the origin so that the lowest joint of
// the rest pose touches the floor (y = 0).
Eigen::Vector3d bind_root_position(const SkeletalMotion& motion);

// A flat-shaded triangle mesh: one slim octahedron per bone, every vertex bound with weight 1 to
// the bone's parent joint (whose rotation moves the bone), plus a 6 cm tip beyond each leaf
// joint bound to the leaf itself, so every joint carries some vertices.
struct StickMesh {
  std::vector<Eigen::Vector3f> positions;
  std::vector<Eigen::Vector3f> normals;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::vector<int> vertex_joint;  // the joint each vertex is bound to
};

// Builds the mesh around the bones of `pose` (normally the bind pose). Bones of zero length are
// skipped.
StickMesh build_stick_mesh(const Pose& pose);

}  // namespace wheelpose::motion
