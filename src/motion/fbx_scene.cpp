#include "motion/fbx_scene.h"

#include <algorithm>
#include <bit>
#include <cstdio>
#include <iterator>
#include <string>

#include "core/error.h"

namespace wheelpose::motion::fbx {

namespace {

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

std::vector<double> translation_matrix(const Eigen::Vector3d& t) {
  // Column-major, as FBX stores matrices.
  return {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, t.x(), t.y(), t.z(), 1};
}

std::vector<Property> xyz(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

Node header_extension(const std::string& title, Encoding encoding) {
  Node header{"FBXHeaderExtension", {}, {}};
  header.add("FBXHeaderVersion", {std::int32_t{1003}});
  header.add("FBXVersion", {static_cast<std::int32_t>(kVersion)});
  if (encoding == Encoding::kBinary) header.add("EncryptionType", {std::int32_t{0}});
  // A fixed date keeps the file a pure function of its content.
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
  meta.add("Title", {title});
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

std::optional<std::string> name_problem(std::string_view name) {
  if (name.find("::") != std::string_view::npos) return "contains '::', FBX's class separator";
  for (char c : name) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte < 0x20 || byte == 0x7f) return "contains a control character";
    if (c == '"') return "contains a double quote";
  }
  return std::nullopt;
}

Node& SceneBuilder::add_object(const char* type, std::int64_t id, std::string_view name,
                               std::string_view object_class, std::string_view subclass) {
  return objects_.add(type, {id, object_name(name, object_class), std::string(subclass)});
}

void SceneBuilder::connect(std::int64_t child, std::int64_t parent) {
  connections_.add("C", {std::string("OO"), child, parent});
}

void SceneBuilder::connect_property(std::int64_t child, std::int64_t parent,
                                    std::string_view property) {
  connections_.add("C", {std::string("OP"), child, parent, std::string(property)});
}

std::int64_t SceneBuilder::add_model(std::string_view name, std::string_view subclass,
                                     std::int64_t parent, const Eigen::Vector3d& translation,
                                     EulerOrder order) {
  const std::int64_t id = new_id();
  Node& model = add_object("Model", id, name, "Model", subclass);
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
  connect(id, parent);
  return id;
}

std::int64_t SceneBuilder::add_bone(std::string_view name, std::int64_t parent,
                                    const Eigen::Vector3d& translation, EulerOrder order) {
  const std::int64_t model = add_model(name, "LimbNode", parent, translation, order);
  const std::int64_t attribute = new_id();
  Node& skeleton = add_object("NodeAttribute", attribute, name, "NodeAttribute", "LimbNode");
  skeleton.add("TypeFlags", {std::string("Skeleton")});
  connect(attribute, model);
  return model;
}

std::int64_t SceneBuilder::add_geometry(std::int64_t model, std::string_view name,
                                        const MeshGeometry& mesh) {
  const std::int64_t id = new_id();
  Node& geometry = add_object("Geometry", id, name, "Geometry", "Mesh");
  std::vector<double> vertices, normals;
  vertices.reserve(3 * mesh.positions.size());
  normals.reserve(3 * mesh.normals.size());
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    for (int axis = 0; axis < 3; ++axis) {
      vertices.push_back(mesh.positions[v][axis]);
      normals.push_back(mesh.normals[v][axis]);
    }
  }
  std::vector<std::int32_t> polygon_vertices;
  polygon_vertices.reserve(3 * mesh.triangles.size());
  for (const auto& triangle : mesh.triangles) {
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
  connect(id, model);
  return id;
}

std::int64_t SceneBuilder::add_material(std::string_view name, const Eigen::Vector3d& colour) {
  const std::int64_t id = new_id();
  Node& material = add_object("Material", id, name, "Material", "");
  material.add("Version", {std::int32_t{102}});
  material.add("ShadingModel", {std::string("lambert")});
  material.add("MultiLayer", {std::int32_t{0}});
  Node& p = material.add("Properties70");
  add_p(p, "DiffuseColor", "Color", "", "A", xyz(colour));
  add_p(p, "DiffuseFactor", "Number", "", "A", {1.0});
  return id;
}

void SceneBuilder::add_skin(std::int64_t geometry, std::string_view name,
                            const std::vector<Cluster>& clusters) {
  const std::int64_t skin_id = new_id();
  Node& skin = add_object("Deformer", skin_id, name, "Deformer", "Skin");
  skin.add("Version", {std::int32_t{101}});
  skin.add("Link_DeformAcuracy", {50.0});
  connect(skin_id, geometry);
  for (const Cluster& c : clusters) {
    const std::int64_t cluster_id = new_id();
    Node& cluster = add_object("Deformer", cluster_id, c.name, "SubDeformer", "Cluster");
    cluster.add("Version", {std::int32_t{100}});
    cluster.add("UserData", {std::string(), std::string()});
    cluster.add("Indexes", {c.indexes});
    cluster.add("Weights", {c.weights});
    // Transform is the mesh relative to the bone (the mesh sits at the origin), TransformLink
    // the bone's world matrix at binding.
    cluster.add("Transform", {translation_matrix(-c.bind_position)});
    cluster.add("TransformLink", {translation_matrix(c.bind_position)});
    connect(cluster_id, skin_id);
    connect(c.bone_model, cluster_id);
  }
}

void SceneBuilder::add_bind_pose(
    const std::vector<std::pair<std::int64_t, Eigen::Vector3d>>& nodes) {
  Node& pose = add_object("Pose", new_id(), "BIND_POSES", "Pose", "BindPose");
  pose.add("Type", {std::string("BindPose")});
  pose.add("Version", {std::int32_t{100}});
  pose.add("NbPoseNodes", {static_cast<std::int32_t>(nodes.size())});
  for (const auto& [model, position] : nodes) {
    Node& node = pose.add("PoseNode");
    node.add("Node", {model});
    node.add("Matrix", {translation_matrix(position)});
  }
}

void SceneBuilder::begin_animation(std::string_view name, std::vector<std::int64_t> key_times) {
  WHEELPOSE_CHECK(!key_times.empty() && layer_ == 0);
  animation_ = std::string(name);
  key_times_ = std::move(key_times);
  const std::int64_t stack_id = new_id();
  Node& stack = add_object("AnimationStack", stack_id, name, "AnimStack", "");
  Node& stack_p = stack.add("Properties70");
  for (const char* property : {"LocalStart", "LocalStop", "ReferenceStart", "ReferenceStop"}) {
    const bool start = std::string_view(property).ends_with("Start");
    add_p(stack_p, property, "KTime", "Time", "", {start ? std::int64_t{0} : key_times_.back()});
  }
  layer_ = new_id();
  add_object("AnimationLayer", layer_, "BaseLayer", "AnimLayer", "");
  connect(layer_, stack_id);
}

void SceneBuilder::add_curves(std::int64_t model, std::string_view short_name,
                              std::string_view property,
                              const std::vector<Eigen::Vector3d>& values) {
  WHEELPOSE_CHECK(layer_ != 0 && values.size() == key_times_.size());
  const std::int64_t node_id = new_id();
  Node& curve_node = add_object("AnimationCurveNode", node_id, short_name, "AnimCurveNode", "");
  Node& p = curve_node.add("Properties70");
  static constexpr const char* kChannels[3] = {"d|X", "d|Y", "d|Z"};
  for (int axis = 0; axis < 3; ++axis) {
    add_p(p, kChannels[axis], "Number", "", "A", {values.front()[axis]});
  }
  connect(node_id, layer_);
  connect_property(node_id, model, property);
  const auto key_count = static_cast<std::int32_t>(values.size());
  for (int axis = 0; axis < 3; ++axis) {
    const std::int64_t curve_id = new_id();
    Node& curve = add_object("AnimationCurve", curve_id, "", "AnimCurve", "");
    curve.add("Default", {values.front()[axis]});
    curve.add("KeyVer", {std::int32_t{4009}});
    curve.add("KeyTime", {key_times_});
    std::vector<float> key_values;
    key_values.reserve(values.size());
    for (const Eigen::Vector3d& v : values) key_values.push_back(static_cast<float>(v[axis]));
    curve.add("KeyValueFloat", {std::move(key_values)});
    // One attribute set shared by all keys (KeyAttrRefCount = key count).
    curve.add("KeyAttrFlags", {std::vector<std::int32_t>{kLinearKeyFlags}});
    curve.add("KeyAttrDataFloat",
              {std::vector<float>{0, 0, std::bit_cast<float>(kDefaultTangentBits), 0}});
    curve.add("KeyAttrRefCount", {std::vector<std::int32_t>{key_count}});
    connect_property(curve_id, node_id, kChannels[axis]);
  }
}

std::vector<Node> SceneBuilder::finish(Encoding encoding, const FrameRate& rate, double fps) {
  WHEELPOSE_CHECK(layer_ != 0);
  const std::int64_t stop = key_times_.back();
  std::vector<Node> document;
  document.push_back(header_extension(animation_, encoding));
  if (encoding == Encoding::kBinary) {
    document.push_back(
        {"FileId", {Bytes{std::string(std::begin(kFileId), std::end(kFileId))}}, {}});
    document.push_back({"CreationTime", {std::string(kCreationTime)}, {}});
    document.push_back({"Creator", {std::string(kCreator)}, {}});
  }
  document.push_back(global_settings(rate, fps, stop));
  Node documents{"Documents", {}, {}};
  documents.add("Count", {std::int32_t{1}});
  Node& doc = documents.add("Document", {new_id(), std::string("Scene"), std::string("Scene")});
  Node& doc_p = doc.add("Properties70");
  add_p(doc_p, "SourceObject", "object", "", "");
  add_p(doc_p, "ActiveAnimStackName", "KString", "", "", {animation_});
  doc.add("RootNode", {std::int64_t{0}});
  document.push_back(std::move(documents));
  document.push_back({"References", {}, {}});
  document.push_back(definitions(objects_));
  document.push_back(std::move(objects_));
  document.push_back(std::move(connections_));
  Node takes{"Takes", {}, {}};
  takes.add("Current", {animation_});
  Node& take = takes.add("Take", {animation_});
  take.add("FileName", {animation_ + ".tak"});
  take.add("LocalTime", {std::int64_t{0}, stop});
  take.add("ReferenceTime", {std::int64_t{0}, stop});
  document.push_back(std::move(takes));
  return document;
}

}  // namespace wheelpose::motion::fbx
