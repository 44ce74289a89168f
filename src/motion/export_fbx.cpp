#include "motion/export_fbx.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <string_view>
#include <utility>

#include "core/atomic_file.h"
#include "core/error.h"
#include "motion/euler_curves.h"
#include "motion/fbx_ascii.h"
#include "motion/fbx_binary.h"
#include "motion/fbx_time.h"
#include "motion/stick_figure.h"

namespace wheelpose::motion {

namespace {

using fbx::add_p;
using fbx::Node;
using fbx::object_name;

constexpr const char* kRootNodeName = "wheelpose_root";
constexpr const char* kMeshName = "stick_figure";
constexpr const char* kCreator = "WheelPose";
// Linear interpolation | auto tangent | generic time-independent | generic clamp progressive:
// what the FBX SDK writes for linear keys.
constexpr std::int32_t kLinearKeyFlags = (1 << 2) | (1 << 8) | (1 << 13) | (1 << 14);
// KeyAttrDataFloat's third value as the FBX SDK writes it for default tangents (packed tangent
// weights, not a meaningful float; ASCII files print it as the integer 255790911).
constexpr std::uint32_t kDefaultTangentBits = 255790911;
// FileId and CreationTime of binary files: the FBX SDK checks FileId and the footer's id
// (fbx_binary.cpp) against CreationTime, so writers without the SDK use this fixed, consistent
// set.
constexpr unsigned char kFileId[16] = {0x28, 0xb3, 0x2a, 0xeb, 0xb6, 0x24, 0xcc, 0xc2,
                                       0xbf, 0xc8, 0xb0, 0x2a, 0xa9, 0x2b, 0xfc, 0xf1};
constexpr const char* kCreationTime = "1970-01-01 10:00:00:000";

std::string printable(std::string_view text) {
  std::string out;
  for (char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte < 0x20 || byte == 0x7f) {
      char escaped[8];
      std::snprintf(escaped, sizeof(escaped), "\\x%02x", byte);
      out += escaped;
    } else {
      out += c;
    }
  }
  return out;
}

[[noreturn]] void reject(const SkeletalMotion& motion, const std::string& what) {
  throw Error("motion '" + printable(motion.name) + "': cannot write FBX: " + what,
              ErrorKind::kBadInput);
}

// FBX keeps an object's class beside its name ("name\x00\x01Class" in binary, "Class::name" in
// ASCII), and ASCII strings are quoted without escapes.
void check_name(const SkeletalMotion& motion, std::string_view name) {
  const auto bad = [&](const char* why) {
    reject(motion, "the name '" + printable(name) + "' " + why);
  };
  if (name.find("::") != std::string_view::npos) bad("contains '::', FBX's class separator");
  for (char c : name) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte < 0x20 || byte == 0x7f) bad("contains a control character");
    if (c == '"') bad("contains a double quote");
  }
}

std::string animation_name(const SkeletalMotion& motion) {
  return motion.name.empty() ? "motion" : motion.name;
}

std::vector<double> translation_matrix(const Eigen::Vector3d& t) {
  // Column-major, as FBX stores matrices.
  return {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, t.x(), t.y(), t.z(), 1};
}

std::vector<fbx::Property> xyz(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

// The Objects and Connections sections being filled.
class Scene {
 public:
  Node objects{"Objects", {}, {}};
  Node connections{"Connections", {}, {}};

  std::int64_t new_id() { return next_id_++; }

  Node& add_object(const char* type, std::int64_t id, std::string_view name,
                   std::string_view object_class, std::string_view subclass) {
    return objects.add(type, {id, object_name(name, object_class), std::string(subclass)});
  }
  void connect(std::int64_t child, std::int64_t parent) {
    connections.add("C", {std::string("OO"), child, parent});
  }
  void connect_property(std::int64_t child, std::int64_t parent, std::string_view property) {
    connections.add("C", {std::string("OP"), child, parent, std::string(property)});
  }

 private:
  std::int64_t next_id_ = 1000000;
};

Node& add_model(Scene& scene, std::int64_t id, std::string_view name, std::string_view subclass,
                const Eigen::Vector3d& translation, EulerOrder order) {
  Node& model = scene.add_object("Model", id, name, "Model", subclass);
  model.add("Version", {std::int32_t{232}});
  Node& p = model.add("Properties70");
  add_p(p, "RotationOrder", "enum", "", "", {static_cast<std::int32_t>(order)});
  // Without RotationActive the FBX SDK ignores RotationOrder.
  add_p(p, "RotationActive", "bool", "", "", {std::int32_t{1}});
  add_p(p, "InheritType", "enum", "", "", {std::int32_t{1}});
  add_p(p, "DefaultAttributeIndex", "int", "Integer", "", {std::int32_t{0}});
  add_p(p, "Lcl Translation", "Lcl Translation", "", "A", xyz(translation));
  add_p(p, "Lcl Rotation", "Lcl Rotation", "", "A", xyz(Eigen::Vector3d::Zero()));
  add_p(p, "Lcl Scaling", "Lcl Scaling", "", "A", xyz(Eigen::Vector3d::Ones()));
  model.add("Culling", {std::string("CullingOff")});
  return model;
}

// One AnimationCurveNode (X, Y, Z) of `model`'s `property`, one linear key per frame.
void add_curves(Scene& scene, std::int64_t layer, std::int64_t model, std::string_view short_name,
                std::string_view property, const std::vector<Eigen::Vector3d>& values,
                const std::vector<std::int64_t>& times) {
  const std::int64_t node_id = scene.new_id();
  Node& curve_node =
      scene.add_object("AnimationCurveNode", node_id, short_name, "AnimCurveNode", "");
  Node& p = curve_node.add("Properties70");
  static constexpr const char* kChannels[3] = {"d|X", "d|Y", "d|Z"};
  for (int axis = 0; axis < 3; ++axis) {
    add_p(p, kChannels[axis], "Number", "", "A", {values.front()[axis]});
  }
  scene.connect(node_id, layer);
  scene.connect_property(node_id, model, property);
  const auto key_count = static_cast<std::int32_t>(values.size());
  for (int axis = 0; axis < 3; ++axis) {
    const std::int64_t curve_id = scene.new_id();
    Node& curve = scene.add_object("AnimationCurve", curve_id, "", "AnimCurve", "");
    curve.add("Default", {values.front()[axis]});
    curve.add("KeyVer", {std::int32_t{4009}});
    curve.add("KeyTime", {times});
    std::vector<float> key_values;
    key_values.reserve(values.size());
    for (const Eigen::Vector3d& v : values) key_values.push_back(static_cast<float>(v[axis]));
    curve.add("KeyValueFloat", {std::move(key_values)});
    // One attribute set shared by all keys (KeyAttrRefCount = key count).
    curve.add("KeyAttrFlags", {std::vector<std::int32_t>{kLinearKeyFlags}});
    curve.add("KeyAttrDataFloat",
              {std::vector<float>{0, 0, std::bit_cast<float>(kDefaultTangentBits), 0}});
    curve.add("KeyAttrRefCount", {std::vector<std::int32_t>{key_count}});
    scene.connect_property(curve_id, node_id, kChannels[axis]);
  }
}

void add_mesh(Scene& scene, std::int64_t mesh_model, const StickMesh& stick,
              const std::vector<std::int64_t>& joint_models, const Pose& bind_pose) {
  const std::int64_t geometry_id = scene.new_id();
  Node& geometry = scene.add_object("Geometry", geometry_id, kMeshName, "Geometry", "Mesh");
  std::vector<double> vertices, normals;
  for (std::size_t v = 0; v < stick.positions.size(); ++v) {
    for (int axis = 0; axis < 3; ++axis) {
      vertices.push_back(stick.positions[v][axis]);
      normals.push_back(stick.normals[v][axis]);
    }
  }
  std::vector<std::int32_t> polygon_vertices;
  for (const auto& triangle : stick.triangles) {
    polygon_vertices.push_back(static_cast<std::int32_t>(triangle[0]));
    polygon_vertices.push_back(static_cast<std::int32_t>(triangle[1]));
    polygon_vertices.push_back(-static_cast<std::int32_t>(triangle[2]) - 1);  // ends the polygon
  }
  geometry.add("Vertices", {std::move(vertices)});
  geometry.add("PolygonVertexIndex", {std::move(polygon_vertices)});
  geometry.add("GeometryVersion", {std::int32_t{124}});
  Node& normal_layer = geometry.add("LayerElementNormal", {std::int32_t{0}});
  normal_layer.add("Version", {std::int32_t{101}});
  normal_layer.add("Name", {std::string()});
  normal_layer.add("MappingInformationType", {std::string("ByVertice")});
  normal_layer.add("ReferenceInformationType", {std::string("Direct")});
  normal_layer.add("Normals", {std::move(normals)});
  Node& material_layer = geometry.add("LayerElementMaterial", {std::int32_t{0}});
  material_layer.add("Version", {std::int32_t{101}});
  material_layer.add("Name", {std::string()});
  material_layer.add("MappingInformationType", {std::string("AllSame")});
  material_layer.add("ReferenceInformationType", {std::string("IndexToDirect")});
  material_layer.add("Materials", {std::vector<std::int32_t>{0}});
  Node& layer = geometry.add("Layer", {std::int32_t{0}});
  layer.add("Version", {std::int32_t{100}});
  for (const char* element : {"LayerElementNormal", "LayerElementMaterial"}) {
    Node& entry = layer.add("LayerElement");
    entry.add("Type", {std::string(element)});
    entry.add("TypedIndex", {std::int32_t{0}});
  }
  scene.connect(geometry_id, mesh_model);

  const std::int64_t material_id = scene.new_id();
  Node& material = scene.add_object("Material", material_id, kMeshName, "Material", "");
  material.add("Version", {std::int32_t{102}});
  material.add("ShadingModel", {std::string("lambert")});
  material.add("MultiLayer", {std::int32_t{0}});
  Node& material_p = material.add("Properties70");
  add_p(material_p, "DiffuseColor", "Color", "", "A", {0.6, 0.6, 0.6});
  add_p(material_p, "DiffuseFactor", "Number", "", "A", {1.0});
  scene.connect(material_id, mesh_model);

  // Skin: one cluster per joint; every vertex follows one joint with weight 1.
  const std::int64_t skin_id = scene.new_id();
  Node& skin = scene.add_object("Deformer", skin_id, kMeshName, "Deformer", "Skin");
  skin.add("Version", {std::int32_t{101}});
  skin.add("Link_DeformAcuracy", {50.0});
  scene.connect(skin_id, geometry_id);
  for (int joint = 0; joint < kJointCount; ++joint) {
    const std::int64_t cluster_id = scene.new_id();
    Node& cluster =
        scene.add_object("Deformer", cluster_id, joint_name(joint), "SubDeformer", "Cluster");
    cluster.add("Version", {std::int32_t{100}});
    cluster.add("UserData", {std::string(), std::string()});
    std::vector<std::int32_t> indexes;
    for (std::size_t v = 0; v < stick.vertex_joint.size(); ++v) {
      if (stick.vertex_joint[v] == joint) indexes.push_back(static_cast<std::int32_t>(v));
    }
    std::vector<double> weights(indexes.size(), 1.0);
    cluster.add("Indexes", {std::move(indexes)});
    cluster.add("Weights", {std::move(weights)});
    // Transform is stored relative to the bone (mesh at the origin), TransformLink is the
    // bone's world matrix at binding; joints carry no rotation in the bind pose.
    cluster.add("Transform", {translation_matrix(-bind_pose[joint])});
    cluster.add("TransformLink", {translation_matrix(bind_pose[joint])});
    scene.connect(cluster_id, skin_id);
    scene.connect(joint_models[joint], cluster_id);
  }
}

void add_bind_pose(Scene& scene, std::int64_t root_model, std::int64_t mesh_model,
                   const std::vector<std::int64_t>& joint_models, const Pose& bind_pose) {
  Node& pose = scene.add_object("Pose", scene.new_id(), "BIND_POSES", "Pose", "BindPose");
  pose.add("Type", {std::string("BindPose")});
  pose.add("Version", {std::int32_t{100}});
  pose.add("NbPoseNodes", {std::int32_t{kJointCount + 2}});
  auto add_node = [&pose](std::int64_t model, const Eigen::Vector3d& position) {
    Node& node = pose.add("PoseNode");
    node.add("Node", {model});
    node.add("Matrix", {translation_matrix(position)});
  };
  add_node(root_model, Eigen::Vector3d::Zero());
  add_node(mesh_model, Eigen::Vector3d::Zero());
  for (int joint = 0; joint < kJointCount; ++joint) add_node(joint_models[joint], bind_pose[joint]);
}

Node header_extension(const SkeletalMotion& motion, FbxEncoding encoding) {
  Node header{"FBXHeaderExtension", {}, {}};
  header.add("FBXHeaderVersion", {std::int32_t{1003}});
  header.add("FBXVersion", {static_cast<std::int32_t>(kFbxVersion)});
  if (encoding == FbxEncoding::kBinary) header.add("EncryptionType", {std::int32_t{0}});
  // A fixed date keeps the file a pure function of the motion.
  Node& stamp = header.add("CreationTimeStamp");
  static constexpr std::pair<const char*, std::int32_t> kStamp[] = {
      {"Version", 1000}, {"Year", 1970}, {"Month", 1},  {"Day", 1},
      {"Hour", 0},       {"Minute", 0},  {"Second", 0}, {"Millisecond", 0}};
  for (const auto& [field, value] : kStamp) stamp.add(field, {value});
  header.add("Creator", {std::string(kCreator)});
  Node& info =
      header.add("SceneInfo", {object_name("GlobalInfo", "SceneInfo"), std::string("UserData")});
  info.add("Type", {std::string("UserData")});
  info.add("Version", {std::int32_t{100}});
  Node& meta = info.add("MetaData");
  meta.add("Version", {std::int32_t{100}});
  meta.add("Title", {animation_name(motion)});
  for (const char* field : {"Subject", "Author", "Keywords", "Revision", "Comment"}) {
    meta.add(field, {std::string()});
  }
  return header;
}

Node global_settings(const FrameRate& rate, double fps, std::int64_t stop) {
  Node settings{"GlobalSettings", {}, {}};
  settings.add("Version", {std::int32_t{1000}});
  Node& p = settings.add("Properties70");
  // +Y up, +Z front, +X right-handed side: the glb's frame.
  static constexpr std::pair<const char*, std::int32_t> kAxes[] = {
      {"UpAxis", 1},    {"UpAxisSign", 1},    {"FrontAxis", 2},      {"FrontAxisSign", 1},
      {"CoordAxis", 0}, {"CoordAxisSign", 1}, {"OriginalUpAxis", 1}, {"OriginalUpAxisSign", 1}};
  for (const auto& [name, value] : kAxes) add_p(p, name, "int", "Integer", "", {value});
  // Centimetres per unit: 1 unit = 1 m.
  add_p(p, "UnitScaleFactor", "double", "Number", "", {100.0});
  add_p(p, "OriginalUnitScaleFactor", "double", "Number", "", {100.0});
  add_p(p, "AmbientColor", "ColorRGB", "Color", "", {0.0, 0.0, 0.0});
  add_p(p, "DefaultCamera", "KString", "", "", {std::string("Producer Perspective")});
  add_p(p, "TimeMode", "enum", "", "", {std::int32_t{fbx_time_mode(rate)}});
  add_p(p, "TimeProtocol", "enum", "", "", {std::int32_t{2}});
  add_p(p, "SnapOnFrameMode", "enum", "", "", {std::int32_t{0}});
  add_p(p, "TimeSpanStart", "KTime", "Time", "", {std::int64_t{0}});
  add_p(p, "TimeSpanStop", "KTime", "Time", "", {stop});
  add_p(p, "CustomFrameRate", "double", "Number", "", {fps});
  add_p(p, "TimeMarker", "Compound", "", "");
  add_p(p, "CurrentTimeMarker", "int", "Integer", "", {std::int32_t{-1}});
  return settings;
}

Node definitions(const Node& objects) {
  std::vector<std::pair<std::string, std::int32_t>> counts = {{"GlobalSettings", 1}};
  for (const Node& object : objects.children) {
    auto it = std::find_if(counts.begin(), counts.end(),
                           [&](const auto& entry) { return entry.first == object.name; });
    if (it == counts.end()) {
      counts.emplace_back(object.name, 1);
    } else {
      ++it->second;
    }
  }
  std::int32_t total = 0;
  for (const auto& entry : counts) total += entry.second;
  Node definitions{"Definitions", {}, {}};
  definitions.add("Version", {std::int32_t{100}});
  definitions.add("Count", {total});
  for (const auto& [type, count] : counts) {
    definitions.add("ObjectType", {type}).add("Count", {count});
  }
  return definitions;
}

}  // namespace

std::vector<Node> fbx_document(const SkeletalMotion& motion, FbxEncoding encoding) {
  check_exportable(motion, "FBX");
  if (!(motion.fps >= kMinFrameRate && motion.fps <= kMaxFrameRate)) {
    reject(motion, "fps " + std::to_string(motion.fps) + " is outside what FBX time can hold");
  }
  check_name(motion, motion.name);
  const std::string animation = animation_name(motion);
  const FrameRate rate = exact_frame_rate(motion.fps);
  const std::size_t frames = motion.frame_count();
  std::vector<std::int64_t> times(frames);
  for (std::size_t f = 0; f < frames; ++f) {
    times[f] = fbx_frame_time(static_cast<std::int64_t>(f), rate);
  }
  const std::int64_t stop = times.back();

  const Eigen::Vector3d bind_root = bind_root_position(motion);
  const Pose bind_pose = rest_pose(motion, bind_root);
  Scene scene;

  const std::int64_t root_model = scene.new_id();
  add_model(scene, root_model, kRootNodeName, "Null", Eigen::Vector3d::Zero(), EulerOrder::kXYZ);
  scene.connect(root_model, 0);
  const std::int64_t mesh_model = scene.new_id();
  add_model(scene, mesh_model, kMeshName, "Mesh", Eigen::Vector3d::Zero(), EulerOrder::kXYZ);
  scene.connect(mesh_model, root_model);

  std::vector<std::int64_t> joint_models(kJointCount);
  std::vector<EulerOrder> orders(kJointCount);
  std::vector<std::vector<Eigen::Quaterniond>> rotations(kJointCount);
  for (int joint : joints_parent_first()) {
    for (std::size_t f = 0; f < frames; ++f) {
      rotations[joint].push_back(motion.local_rotations[f][joint].normalized());
    }
    orders[joint] = best_euler_order(rotations[joint]);
    joint_models[joint] = scene.new_id();
    const int parent = joint_parent(joint);
    add_model(scene, joint_models[joint], joint_name(joint), "LimbNode",
              parent < 0 ? bind_root : motion.rest_offsets[joint], orders[joint]);
    scene.connect(joint_models[joint], parent < 0 ? root_model : joint_models[parent]);
    const std::int64_t attribute = scene.new_id();
    Node& skeleton = scene.add_object("NodeAttribute", attribute, joint_name(joint),
                                      "NodeAttribute", "LimbNode");
    skeleton.add("TypeFlags", {std::string("Skeleton")});
    scene.connect(attribute, joint_models[joint]);
  }
  add_mesh(scene, mesh_model, build_stick_mesh(bind_pose), joint_models, bind_pose);
  add_bind_pose(scene, root_model, mesh_model, joint_models, bind_pose);

  const std::int64_t stack_id = scene.new_id();
  Node& stack = scene.add_object("AnimationStack", stack_id, animation, "AnimStack", "");
  Node& stack_p = stack.add("Properties70");
  for (const char* name : {"LocalStart", "LocalStop", "ReferenceStart", "ReferenceStop"}) {
    const bool start = std::string_view(name).ends_with("Start");
    add_p(stack_p, name, "KTime", "Time", "", {start ? std::int64_t{0} : stop});
  }
  const std::int64_t layer_id = scene.new_id();
  scene.add_object("AnimationLayer", layer_id, "BaseLayer", "AnimLayer", "");
  scene.connect(layer_id, stack_id);
  add_curves(scene, layer_id, joint_models[kPelvis], "T", "Lcl Translation", motion.root_positions,
             times);
  for (int joint : joints_parent_first()) {
    std::vector<Eigen::Vector3d> degrees = continuous_euler(rotations[joint], orders[joint]);
    for (Eigen::Vector3d& angles : degrees) angles *= 180.0 / std::numbers::pi;
    add_curves(scene, layer_id, joint_models[joint], "R", "Lcl Rotation", degrees, times);
  }

  std::vector<Node> document;
  document.push_back(header_extension(motion, encoding));
  if (encoding == FbxEncoding::kBinary) {
    document.push_back(
        {"FileId", {fbx::Bytes{std::string(std::begin(kFileId), std::end(kFileId))}}, {}});
    document.push_back({"CreationTime", {std::string(kCreationTime)}, {}});
    document.push_back({"Creator", {std::string(kCreator)}, {}});
  }
  document.push_back(global_settings(rate, motion.fps, stop));
  Node documents{"Documents", {}, {}};
  documents.add("Count", {std::int32_t{1}});
  Node& doc =
      documents.add("Document", {scene.new_id(), std::string("Scene"), std::string("Scene")});
  Node& doc_p = doc.add("Properties70");
  add_p(doc_p, "SourceObject", "object", "", "");
  add_p(doc_p, "ActiveAnimStackName", "KString", "", "", {animation});
  doc.add("RootNode", {std::int64_t{0}});
  document.push_back(std::move(documents));
  document.push_back({"References", {}, {}});
  document.push_back(definitions(scene.objects));
  document.push_back(std::move(scene.objects));
  document.push_back(std::move(scene.connections));
  Node takes{"Takes", {}, {}};
  takes.add("Current", {animation});
  Node& take = takes.add("Take", {animation});
  take.add("FileName", {animation + ".tak"});
  take.add("LocalTime", {std::int64_t{0}, stop});
  take.add("ReferenceTime", {std::int64_t{0}, stop});
  document.push_back(std::move(takes));
  return document;
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
