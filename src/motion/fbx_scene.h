#pragma once
// The objects of an animated, skinned FBX scene and the document around them, shared by every
// FBX wheelpose writes (a seated clip's stick figure, export_fbx.h; a rigged person,
// body/rigged_fbx.h). The builder hands out object ids in call order, so equal calls give equal
// documents, and keeps the FBX SDK's conventions in one place:
//  * models (Null, Mesh, LimbNode) with RotationOrder/RotationActive and rest translations;
//  * meshes as triangles with per-vertex normals and one material for the whole mesh;
//  * skins as one cluster per bone, Transform and TransformLink as Blender's exporter writes
//    them for a mesh at the origin (the bone's inverse bind and bind matrices), plus a BindPose;
//  * one animation stack with one layer; curves with one linear key per frame at exact ticks;
//  * GlobalSettings with +Y up, +Z front, metres, the clip's TimeMode and span.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "motion/euler_curves.h"
#include "motion/fbx_node.h"
#include "motion/fbx_time.h"

namespace wheelpose::motion::fbx {

enum class Encoding { kBinary, kAscii };
inline constexpr std::uint32_t kVersion = 7400;

// Why FBX cannot hold `name` as an object name ("::" is its class separator; ASCII strings are
// quoted without escapes), or nullopt when it can.
std::optional<std::string> name_problem(std::string_view name);
// `text` with control characters shown as \xNN, for error messages.
std::string printable(std::string_view text);

struct MeshGeometry {
  std::vector<Eigen::Vector3d> positions;
  std::vector<Eigen::Vector3d> normals;  // per vertex
  std::vector<std::array<unsigned, 3>> triangles;
};

// One bone's share of a skinned mesh: the vertices it moves and by how much, and where the bone
// was when the mesh was bound (bones carry no rotation in the bind pose).
struct Cluster {
  std::string name;
  std::int64_t bone_model = 0;
  Eigen::Vector3d bind_position = Eigen::Vector3d::Zero();
  std::vector<std::int32_t> indexes;
  std::vector<double> weights;
};

class SceneBuilder {
 public:
  std::int64_t new_id() { return next_id_++; }

  // A Model (subclass Null, Mesh or LimbNode) under `parent` (0: the scene root).
  std::int64_t add_model(std::string_view name, std::string_view subclass, std::int64_t parent,
                         const Eigen::Vector3d& translation, EulerOrder order);
  // A LimbNode model and its skeleton NodeAttribute.
  std::int64_t add_bone(std::string_view name, std::int64_t parent,
                        const Eigen::Vector3d& translation, EulerOrder order);
  // The mesh of `model`; returns the Geometry's id.
  std::int64_t add_geometry(std::int64_t model, std::string_view name,
                            const MeshGeometry& geometry);
  // A lambert material of base colour `colour` (linear RGB); use_material gives it to a model.
  std::int64_t add_material(std::string_view name, const Eigen::Vector3d& colour);
  void use_material(std::int64_t material, std::int64_t model) { connect(material, model); }
  // A Skin deformer of `geometry` with one SubDeformer per cluster, each linked to its bone.
  void add_skin(std::int64_t geometry, std::string_view name, const std::vector<Cluster>& clusters);
  // The BindPose: every (model, world position at binding).
  void add_bind_pose(const std::vector<std::pair<std::int64_t, Eigen::Vector3d>>& nodes);

  // The animation stack `name` and its one layer; key times in FBX ticks, one per frame.
  void begin_animation(std::string_view name, std::vector<std::int64_t> key_times);
  // An AnimationCurveNode ("T" or "R") driving `property` ("Lcl Translation", "Lcl Rotation",
  // degrees) of `model`, one X, Y, Z curve with a linear key per frame.
  void add_curves(std::int64_t model, std::string_view short_name, std::string_view property,
                  const std::vector<Eigen::Vector3d>& values);

  // The whole document: header (titled after the animation), GlobalSettings at `rate` (`fps`
  // as CustomFrameRate), definitions, objects, connections and the take. Call once, after
  // begin_animation.
  std::vector<Node> finish(Encoding encoding, const FrameRate& rate, double fps);

 private:
  Node& add_object(const char* type, std::int64_t id, std::string_view name,
                   std::string_view object_class, std::string_view subclass);
  void connect(std::int64_t child, std::int64_t parent);
  void connect_property(std::int64_t child, std::int64_t parent, std::string_view property);

  Node objects_{"Objects", {}, {}};
  Node connections_{"Connections", {}, {}};
  std::int64_t next_id_ = 1000000;
  std::string animation_;
  std::int64_t layer_ = 0;
  std::vector<std::int64_t> key_times_;
};

}  // namespace wheelpose::motion::fbx
