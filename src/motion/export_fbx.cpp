#include "motion/export_fbx.h"

#include <cmath>
#include <numbers>
#include <string>
#include <utility>

#include "core/atomic_file.h"
#include "core/error.h"
#include "motion/euler_curves.h"
#include "motion/fbx_ascii.h"
#include "motion/fbx_binary.h"
#include "motion/fbx_scene.h"
#include "motion/fbx_time.h"
#include "motion/stick_figure.h"

namespace wheelpose::motion {

namespace {

constexpr const char* kRootNodeName = "wheelpose_root";
constexpr const char* kMeshName = "stick_figure";

[[noreturn]] void reject(const SkeletalMotion& motion, const std::string& what) {
  throw Error("motion '" + fbx::printable(motion.name) + "': cannot write FBX: " + what,
              ErrorKind::kBadInput);
}

// The stick figure bound to the joints: every vertex follows one joint with weight 1.
void add_stick_figure(fbx::SceneBuilder& scene, std::int64_t mesh_model,
                      const std::vector<std::int64_t>& joint_models, const Pose& bind_pose) {
  const StickMesh stick = build_stick_mesh(bind_pose);
  fbx::MeshGeometry geometry;
  for (std::size_t v = 0; v < stick.positions.size(); ++v) {
    geometry.positions.push_back(stick.positions[v].cast<double>());
    geometry.normals.push_back(stick.normals[v].cast<double>());
  }
  for (const auto& triangle : stick.triangles) {
    geometry.triangles.push_back({static_cast<unsigned>(triangle[0]),
                                  static_cast<unsigned>(triangle[1]),
                                  static_cast<unsigned>(triangle[2])});
  }
  const std::int64_t geometry_id = scene.add_geometry(mesh_model, kMeshName, geometry);
  scene.use_material(scene.add_material(kMeshName, Eigen::Vector3d(0.6, 0.6, 0.6)), mesh_model);
  std::vector<fbx::Cluster> clusters(kJointCount);
  for (int joint = 0; joint < kJointCount; ++joint) {
    fbx::Cluster& cluster = clusters[joint];
    cluster.name = joint_name(joint);
    cluster.bone_model = joint_models[joint];
    cluster.bind_position = bind_pose[joint];
    for (std::size_t v = 0; v < stick.vertex_joint.size(); ++v) {
      if (stick.vertex_joint[v] == joint) cluster.indexes.push_back(static_cast<std::int32_t>(v));
    }
    cluster.weights.assign(cluster.indexes.size(), 1.0);
  }
  scene.add_skin(geometry_id, kMeshName, clusters);
}

}  // namespace

std::vector<fbx::Node> fbx_document(const SkeletalMotion& motion, FbxEncoding encoding) {
  check_exportable(motion, "FBX");
  if (!(motion.fps >= kMinFrameRate && motion.fps <= kMaxFrameRate)) {
    reject(motion, "fps " + std::to_string(motion.fps) + " is outside what FBX time can hold");
  }
  if (auto problem = fbx::name_problem(motion.name)) {
    reject(motion, "the name '" + fbx::printable(motion.name) + "' " + *problem);
  }
  const std::string animation = motion.name.empty() ? "motion" : motion.name;
  const FrameRate rate = exact_frame_rate(motion.fps);
  const std::size_t frames = motion.frame_count();
  std::vector<std::int64_t> times(frames);
  for (std::size_t f = 0; f < frames; ++f) {
    times[f] = fbx_frame_time(static_cast<std::int64_t>(f), rate);
  }

  const Eigen::Vector3d bind_root = bind_root_position(motion);
  const Pose bind_pose = rest_pose(motion, bind_root);
  fbx::SceneBuilder scene;
  const std::int64_t root_model =
      scene.add_model(kRootNodeName, "Null", 0, Eigen::Vector3d::Zero(), EulerOrder::kXYZ);
  const std::int64_t mesh_model =
      scene.add_model(kMeshName, "Mesh", root_model, Eigen::Vector3d::Zero(), EulerOrder::kXYZ);

  std::vector<std::int64_t> joint_models(kJointCount);
  std::vector<EulerOrder> orders(kJointCount);
  std::vector<std::vector<Eigen::Quaterniond>> rotations(kJointCount);
  for (int joint : joints_parent_first()) {
    for (std::size_t f = 0; f < frames; ++f) {
      rotations[joint].push_back(motion.local_rotations[f][joint].normalized());
    }
    orders[joint] = best_euler_order(rotations[joint]);
    const int parent = joint_parent(joint);
    joint_models[joint] =
        scene.add_bone(joint_name(joint), parent < 0 ? root_model : joint_models[parent],
                       parent < 0 ? bind_root : motion.rest_offsets[joint], orders[joint]);
  }
  add_stick_figure(scene, mesh_model, joint_models, bind_pose);
  std::vector<std::pair<std::int64_t, Eigen::Vector3d>> bind_nodes = {
      {root_model, Eigen::Vector3d::Zero()}, {mesh_model, Eigen::Vector3d::Zero()}};
  for (int joint = 0; joint < kJointCount; ++joint) {
    bind_nodes.emplace_back(joint_models[joint], bind_pose[joint]);
  }
  scene.add_bind_pose(bind_nodes);

  scene.begin_animation(animation, std::move(times));
  scene.add_curves(joint_models[kPelvis], "T", "Lcl Translation", motion.root_positions);
  for (int joint : joints_parent_first()) {
    std::vector<Eigen::Vector3d> degrees = continuous_euler(rotations[joint], orders[joint]);
    for (Eigen::Vector3d& angles : degrees) angles *= 180.0 / std::numbers::pi;
    scene.add_curves(joint_models[joint], "R", "Lcl Rotation", degrees);
  }
  return scene.finish(encoding, rate, motion.fps);
}

void write_fbx(const SkeletalMotion& motion, const std::filesystem::path& path) {
  write_file_atomic(path,
                    fbx::encode_binary(fbx_document(motion, FbxEncoding::kBinary), kFbxVersion));
}

void write_fbx_ascii(const SkeletalMotion& motion, const std::filesystem::path& path) {
  write_file_atomic(path,
                    fbx::encode_ascii(fbx_document(motion, FbxEncoding::kAscii), kFbxVersion));
}

}  // namespace wheelpose::motion
