// FrameDraft → Scene: people built by the body stage, dressed by splitting the body mesh at
// the nearest rig bone, their chairs, empty chairs, occluders and the wall or room.

#include "generate/frame_builder.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "core/error.h"
#include "core/random.h"
#include "scene/primitives.h"

namespace wheelpose::generate {
namespace {

using Eigen::Vector3f;

enum Garment { kSkin = 0, kTop = 1, kBottom = 2, kShoes = 3 };

bool starts_with(const std::string& s, const char* prefix) { return s.rfind(prefix, 0) == 0; }

// What covers the body around each rig bone.
Garment garment_of_bone(const std::string& bone, const Outfit& outfit) {
  if (starts_with(bone, "head") || starts_with(bone, "neck") || starts_with(bone, "hand") ||
      starts_with(bone, "thumb") || starts_with(bone, "index") || starts_with(bone, "middle") ||
      starts_with(bone, "ring") || starts_with(bone, "pinky")) {
    return kSkin;
  }
  if (starts_with(bone, "lowerarm")) return outfit.long_sleeves ? kTop : kSkin;
  if (starts_with(bone, "calf")) return outfit.long_trousers ? kBottom : kSkin;
  if (starts_with(bone, "foot") || starts_with(bone, "ball")) return kShoes;
  if (starts_with(bone, "pelvis") || starts_with(bone, "thigh")) return kBottom;
  return kTop;
}

float segment_distance2(const Vector3f& p, const Vector3f& a, const Vector3f& b) {
  const Vector3f ab = b - a;
  const float len2 = ab.squaredNorm();
  const float t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0f, 1.0f) : 0.0f;
  return (a + t * ab - p).squaredNorm();
}

// Garment per vertex from the nearest bone of the rest (unposed) body.
std::vector<Garment> vertex_garments(const body::Person& person, const body::Rig& rig,
                                     const Outfit& outfit) {
  std::vector<Garment> bone_garment(rig.bones.size());
  for (std::size_t b = 0; b < rig.bones.size(); ++b)
    bone_garment[b] = garment_of_bone(rig.bones[b].name, outfit);
  std::vector<Garment> out(person.rest_vertices.size(), kTop);
  for (std::size_t v = 0; v < person.rest_vertices.size(); ++v) {
    float best = INFINITY;
    for (std::size_t b = 0; b < rig.bones.size(); ++b) {
      const float d = segment_distance2(person.rest_vertices[v], person.rest_bones.head[b],
                                        person.rest_bones.tail[b]);
      if (d < best) {
        best = d;
        out[v] = bone_garment[b];
      }
    }
  }
  return out;
}

// Cylindrical UVs around the rest body so procedural fabric wraps it.
Eigen::Vector2f body_uv(const Vector3f& rest) {
  return Eigen::Vector2f(static_cast<float>(std::atan2(rest.x(), rest.z()) / (2 * M_PI) + 0.5),
                         rest.y() / 1.8f);
}

// A body-stage mesh (chair part, aid, furniture model) placed in the world.
scene::Mesh transformed_mesh(const body::TriMesh& part, const std::string& name,
                             const Eigen::Affine3f& to_world) {
  scene::Mesh mesh;
  mesh.name = name;
  mesh.positions.reserve(part.vertices.size());
  for (const Vector3f& v : part.vertices) mesh.positions.push_back(to_world * v);
  for (const Vector3f& n : part.normals)
    mesh.normals.push_back((to_world.linear() * n).normalized());
  for (const auto& t : part.triangles)
    mesh.triangles.emplace_back(static_cast<int>(t[0]), static_cast<int>(t[1]),
                                static_cast<int>(t[2]));
  return mesh;
}

class SceneAssembler {
 public:
  explicit SceneAssembler(scene::Scene& scene) : scene_(scene) {}

  int add_material(const scene::Material& m) {
    scene_.materials.push_back(m);
    return static_cast<int>(scene_.materials.size()) - 1;
  }
  int add_mesh(scene::Mesh mesh) {
    scene_.meshes.push_back(std::move(mesh));
    return static_cast<int>(scene_.meshes.size()) - 1;
  }
  // One mesh per primitive spec, shared by every instance of it.
  int primitive_mesh(const scene::PrimitiveSpec& spec) {
    const std::string key = spec.type + std::to_string(spec.size.x()) + "," +
                            std::to_string(spec.size.y()) + "," + std::to_string(spec.size.z());
    auto it = primitive_meshes_.find(key);
    if (it != primitive_meshes_.end()) return it->second;
    scene::Mesh mesh = scene::make_primitive(spec);
    mesh.name = spec.type;
    const int index = add_mesh(std::move(mesh));
    primitive_meshes_.emplace(key, index);
    return index;
  }
  // One mesh per furniture model, shared by every instance of it in the frame.
  int furniture_mesh(const FurnitureCatalog& catalog, std::size_t item) {
    const std::string key = "furniture:" + std::to_string(item);
    auto it = primitive_meshes_.find(key);
    if (it != primitive_meshes_.end()) return it->second;
    // The models carry no normals: flat faces keep their hard edges.
    const int index = add_mesh(transformed_mesh(catalog.mesh(item), catalog.items()[item].name,
                                                Eigen::Affine3f::Identity()));
    primitive_meshes_.emplace(key, index);
    return index;
  }
  void add_instance(const std::string& name, int mesh, int material,
                    const Eigen::Matrix4f& transform, std::uint16_t id, std::uint16_t semantic) {
    scene::Instance inst;
    inst.name = name;
    inst.mesh = mesh;
    inst.material = material;
    inst.transform = transform;
    inst.instance_id = id;
    inst.semantic_id = semantic;
    scene_.instances.push_back(std::move(inst));
  }

 private:
  scene::Scene& scene_;
  std::map<std::string, int> primitive_meshes_;
};

Eigen::Matrix4f trs(const Vector3f& position, const Eigen::Quaternionf& rotation,
                    const Vector3f& scale) {
  Eigen::Affine3f a = Eigen::Translation3f(position) * rotation * Eigen::Scaling(scale);
  return a.matrix();
}

void add_chair(SceneAssembler& out, const body::Wheelchair& chair,
               const std::array<Vector3f, 4>& colours, const Eigen::Affine3f& to_world,
               const std::string& name, std::uint16_t id) {
  static const char* kPartNames[] = {"frame", "upholstery", "tyre", "trim"};
  for (int m = 0; m < 4; ++m) {
    scene::Mesh mesh =
        transformed_mesh(body::primitive_mesh(chair, m), name + "_" + kPartNames[m], to_world);
    if (mesh.triangles.empty()) continue;
    scene::Material material;
    material.name = mesh.name;
    material.diffuse = colours[static_cast<std::size_t>(m)];
    material.specular = m == 0 ? 0.4f : 0.05f;
    material.shininess = m == 0 ? 64.0f : 16.0f;
    out.add_instance(mesh.name, out.add_mesh(std::move(mesh)), out.add_material(material),
                     Eigen::Matrix4f::Identity(), id, kSemanticWheelchair);
  }
}

std::array<Vector3f, 4> chair_colours(const body::Wheelchair& chair,
                                      const std::optional<std::array<Vector3f, 4>>& chosen) {
  if (chosen) return *chosen;
  std::array<Vector3f, 4> c;
  for (std::size_t i = 0; i < 4; ++i)
    c[i] = i < chair.colours.size() ? chair.colours[i] : Vector3f(0.2f, 0.2f, 0.2f);
  return c;
}

// Built-in clips in which both hands drive the push rims throughout; their people get the hands
// placed on the rims (body::reach_push_rims). Clips from --motions keep their arms as recorded.
bool pushes_the_rims(const std::string& clip) {
  for (const char* name : {"push_rims_forward", "push_rims_backward", "turn_in_place",
                           "turn_while_rolling", "wheelie", "extreme_ramp_drop"}) {
    if (clip == name) return true;
  }
  return false;
}

motion::PoseRotations clip_pose(const motion::SeatedClip& clip, double time) {
  const std::size_t count = clip.motion.frame_count();
  const double f = std::floor(time * clip.motion.fps);
  const std::size_t frame = f <= 0 ? 0 : std::min(count - 1, static_cast<std::size_t>(f));
  return motion::global_rotations(clip.motion, frame);
}

// The body, split into skin and the outfit's top, bottom and shoes: a worn suit covers the body,
// so what shows of it is skin; otherwise the body is painted by bone.
void add_body(SceneAssembler& out, const body::Person& person, const PersonDraft& p,
              const body::BodyData& body_data, const Eigen::Affine3f& to_world,
              const std::string& name, std::uint16_t id) {
  std::vector<Vector3f> world(person.vertices.size());
  for (std::size_t v = 0; v < world.size(); ++v) world[v] = to_world * person.vertices[v];
  const std::vector<Vector3f> normals = body::vertex_normals(world, person.triangles);
  const bool suited =
      std::any_of(person.garments.begin(), person.garments.end(), [](const body::Garment& g) {
        return g.name.rfind("clothes/", 0) == 0 && g.name.find("shoes") == std::string::npos &&
               (g.name.rfind("clothes/male_", 0) == 0 || g.name.rfind("clothes/female_", 0) == 0);
      });
  const std::vector<Garment> garment =
      suited ? std::vector<Garment>(person.rest_vertices.size(), kSkin)
             : vertex_garments(person, body_data.rig(), p.outfit);
  static const char* kGarmentNames[] = {"skin", "top", "bottom", "shoes"};
  for (int g = kSkin; g <= kShoes; ++g) {
    scene::Mesh mesh;
    mesh.name = name + "_" + kGarmentNames[g];
    std::vector<int> local(world.size(), -1);
    for (const auto& t : person.triangles) {
      if (garment[t[0]] != g) continue;
      Eigen::Vector3i tri;
      for (int c = 0; c < 3; ++c) {
        int& l = local[t[c]];
        if (l < 0) {
          l = static_cast<int>(mesh.positions.size());
          mesh.positions.push_back(world[t[c]]);
          mesh.normals.push_back(normals[t[c]]);
          mesh.uvs.push_back(body_uv(person.rest_vertices[t[c]]));
        }
        tri[c] = l;
      }
      mesh.triangles.push_back(tri);
    }
    if (mesh.triangles.empty()) continue;
    scene::Material material;
    if (g == kSkin) {
      material.name = mesh.name;
      material.diffuse = person.skin;
      material.specular = 0.08f;
      material.shininess = 24.0f;
    } else {
      material = g == kTop ? p.outfit.top : g == kBottom ? p.outfit.bottom : p.outfit.shoes;
      material.name = mesh.name;
    }
    out.add_instance(mesh.name, out.add_mesh(std::move(mesh)), out.add_material(material),
                     Eigen::Matrix4f::Identity(), id, kSemanticPerson);
  }
}

// The MakeHuman clothes, hair, eyebrows and eyes worn, each in the outfit's colour for it.
void add_garments(SceneAssembler& out, const body::Person& person, const PersonDraft& p,
                  const Eigen::Affine3f& to_world, const std::string& name, std::uint16_t id) {
  for (std::size_t gi = 0; gi < person.garments.size(); ++gi) {
    const body::Garment& g = person.garments[gi];
    if (g.triangles.empty()) continue;
    scene::Mesh mesh;
    mesh.name = name + "_" + g.name.substr(g.name.find('/') + 1);
    mesh.positions.reserve(g.vertices.size());
    for (const Vector3f& v : g.vertices) mesh.positions.push_back(to_world * v);
    std::vector<std::array<unsigned, 3>> tris = g.triangles;
    mesh.normals = body::vertex_normals(mesh.positions, tris);
    for (const Vector3f& r : g.rest_vertices) mesh.uvs.push_back(body_uv(r));
    for (const auto& t : tris)
      mesh.triangles.emplace_back(static_cast<int>(t[0]), static_cast<int>(t[1]),
                                  static_cast<int>(t[2]));
    const bool hair = g.name.rfind("hair/", 0) == 0 || g.name.rfind("eyebrows/", 0) == 0;
    const bool eyes = g.name.rfind("eyes/", 0) == 0;
    const bool shoes = g.name.find("shoes") != std::string::npos;
    const bool suit =
        g.name.rfind("clothes/male_", 0) == 0 || g.name.rfind("clothes/female_", 0) == 0;
    scene::Material material = eyes    ? p.outfit.eyes
                               : hair  ? p.outfit.hair
                               : shoes ? p.outfit.shoes
                               : suit  ? p.outfit.top
                                       : p.outfit.bottom;  // hats
    material.name = mesh.name;
    out.add_instance(mesh.name, out.add_mesh(std::move(mesh)), out.add_material(material),
                     Eigen::Matrix4f::Identity(), id, kSemanticPerson);
  }
}

void add_mobility_aid(SceneAssembler& out, const body::Person& person,
                      const Eigen::Affine3f& to_world, const std::string& name, std::size_t k) {
  static const char* kAidParts[] = {"frame", "grips"};
  for (int m = 0; m < static_cast<int>(person.aid.colours.size()); ++m) {
    scene::Mesh mesh = transformed_mesh(body::primitive_mesh(person.aid.parts, m),
                                        name + "_mobility_aid_" + kAidParts[m], to_world);
    if (mesh.triangles.empty()) continue;
    scene::Material material;
    material.name = mesh.name;
    material.diffuse = person.aid.colours[static_cast<std::size_t>(m)];
    material.specular = m == 0 ? 0.5f : 0.05f;
    material.shininess = 64.0f;
    out.add_instance(mesh.name, out.add_mesh(std::move(mesh)), out.add_material(material),
                     Eigen::Matrix4f::Identity(), static_cast<std::uint16_t>(kAidIdBase + k + 1),
                     kSemanticMobilityAid);
  }
}

// The person's keypoints in the world and the attributes its annotation records.
void label_person(const body::Person& person, const body::PersonSpec& spec, const PersonDraft& p,
                  const motion::SeatedClip* clip, const Eigen::Affine3f& to_world,
                  const std::vector<KeypointAnchor>& anchors, std::uint16_t id,
                  LabelPerson& label) {
  label.instance_id = id;
  for (const KeypointAnchor& a : anchors) {
    const bool raised = a.kind == KeypointAnchor::kRaisedHip;
    const Vector3f local = raised ? person.raised_hips[a.index] : person.coco[a.index];
    label.keypoints.push_back(to_world * local);
    label.tolerance.push_back(a.tolerance_m * p.scale);
    // Raised hips exist when the hips do.
    label.present.push_back(person.coco_present[raised ? 11 + a.index : a.index]);
  }
  nlohmann::ordered_json limbs = nlohmann::ordered_json::object();
  for (int l = 0; l < 4; ++l) {
    const auto limb = static_cast<body::Limb>(l);
    if (spec.limbs[l] != body::Cut::kNone)
      limbs[body::limb_name(limb)] = body::cut_name(limb, spec.limbs[l]);
  }
  label.attributes["body"] = spec.params.to_json();
  label.attributes["pool_slot"] = p.pool_slot;
  label.attributes["wheelchair_type"] = body::wheelchair_type_name(person.chair.type);
  label.attributes["limb_difference"] = std::move(limbs);
  label.attributes["mobility_aid"] = body::mobility_aid_name(person.aid.type);
  label.attributes["motion_id"] = clip != nullptr ? clip->motion.name
                                  : spec.wheelchair == body::WheelchairType::kNone ? "rest_standing"
                                                                                   : "rest_seated";
  label.attributes["motion_time"] = clip != nullptr ? std::round(p.time * 1e4) / 1e4 : 0.0;
  label.attributes["scale"] = std::round(static_cast<double>(p.scale) * 1e4) / 1e4;
  // The MakeHuman clothes, hair and eyebrows worn, so train/test asset overlap is checkable.
  label.attributes["assets"] = spec.proxies;
}

void add_person(SceneAssembler& out, const FrameDraft& draft, std::size_t k,
                const body::BodyData& body_data, const std::vector<motion::SeatedClip>& clips,
                const std::vector<KeypointAnchor>& anchors, LabelPerson& label) {
  const PersonDraft& p = draft.people[k];
  body::PersonSpec spec = p.spec;
  const motion::SeatedClip* clip =
      p.clip >= 0 && static_cast<std::size_t>(p.clip) < clips.size() ? &clips[p.clip] : nullptr;
  if (clip != nullptr) {
    spec.pose = clip_pose(*clip, p.time);
    spec.hands_on_rims =
        spec.wheelchair != body::WheelchairType::kNone && pushes_the_rims(clip->motion.name);
  }
  const body::Person person = body::build_person(body_data, spec);

  const Vector3f pelvis = person.joints[motion::kPelvis].cast<float>();
  const Vector3f anchor(pelvis.x(), draft.environment == EnvironmentKind::kRoom ? 0.0f : pelvis.y(),
                        pelvis.z());
  const Eigen::Affine3f to_world = Eigen::Translation3f(p.position) * p.rotation *
                                   Eigen::Scaling(p.scale) * Eigen::Translation3f(-anchor);
  const auto id = static_cast<std::uint16_t>(k + 1);
  const std::string name = "person_" + std::to_string(k + 1);
  add_body(out, person, p, body_data, to_world, name, id);
  add_garments(out, person, p, to_world, name, id);
  add_chair(out, person.chair, chair_colours(person.chair, p.chair_colours), to_world,
            name + "_wheelchair", static_cast<std::uint16_t>(kChairIdBase + k + 1));
  add_mobility_aid(out, person, to_world, name, k);
  label_person(person, spec, p, clip, to_world, anchors, id, label);
}

void add_structure(SceneAssembler& out, const FrameDraft& draft) {
  std::uint16_t id = kStructureIdBase;
  auto plane = [&](const std::string& name, float half_x, float half_z,
                   const scene::Material& material, const Vector3f& position,
                   const Eigen::Quaternionf& rotation) {
    const int mesh = out.primitive_mesh({"plane", Vector3f(half_x, 0, half_z), 1});
    scene::Material m = material;
    m.name = name;
    out.add_instance(name, mesh, out.add_material(m), trs(position, rotation, Vector3f::Ones()),
                     ++id, kSemanticStructure);
  };
  const auto about_x = [](float deg) {
    return Eigen::Quaternionf(
        Eigen::AngleAxisf(deg * static_cast<float>(M_PI / 180), Vector3f::UnitX()));
  };
  const auto about_y = [](float deg) {
    return Eigen::Quaternionf(
        Eigen::AngleAxisf(deg * static_cast<float>(M_PI / 180), Vector3f::UnitY()));
  };
  if (draft.environment == EnvironmentKind::kWall) {
    // Wide enough to fill a 50° view from 25 m away at 16:9.
    plane("wall", 40.0f, 40.0f, draft.wall, Vector3f(0, 0, draft.wall_z), about_x(90));
    return;
  }
  const float hx = draft.room.size.x() / 2, hz = draft.room.size.y() / 2, h = draft.room.height;
  plane("floor", hx, hz, draft.room.floor, Vector3f::Zero(), Eigen::Quaternionf::Identity());
  plane("ceiling", hx, hz, draft.room.walls, Vector3f(0, h, 0), about_x(180));
  // Walls face the room's centre (a plane's front is +Y; +90° about X turns it to +Z).
  plane("wall_back", hx, h / 2, draft.room.walls, Vector3f(0, h / 2, -hz), about_x(90));
  plane("wall_front", hx, h / 2, draft.room.walls, Vector3f(0, h / 2, hz),
        about_y(180) * about_x(90));
  plane("wall_left", hz, h / 2, draft.room.walls, Vector3f(-hx, h / 2, 0),
        about_y(90) * about_x(90));
  plane("wall_right", hz, h / 2, draft.room.walls, Vector3f(hx, h / 2, 0),
        about_y(-90) * about_x(90));
}

scene::PrimitiveSpec object_spec(const std::string& shape) {
  if (shape == "sphere") return {"sphere", Vector3f(0.5f, 0.5f, 0.5f), 16};
  if (shape == "capsule" || shape == "cylinder") return {"capsule", Vector3f(0.3f, 0.2f, 0.3f), 16};
  return {"box", Vector3f(0.5f, 0.5f, 0.5f), 1};
}

}  // namespace

std::vector<KeypointAnchor> resolve_anchors(const KeypointTemplate& keypoint_template) {
  std::vector<KeypointAnchor> anchors;
  for (const KeypointInfo& k : keypoint_template.keypoints) {
    const std::string& a = k.anchor;
    const auto colon = a.find(':');
    const std::string kind = a.substr(0, colon),
                      what = colon == std::string::npos ? "" : a.substr(colon + 1);
    KeypointAnchor anchor;
    if (kind == "raised_hip" && (what == "left" || what == "right")) {
      anchor.kind = KeypointAnchor::kRaisedHip;
      anchor.index = what == "left" ? 0 : 1;
    } else {
      const auto& names = body::coco_names();
      const auto it = std::find(names.begin(), names.end(), what);
      if ((kind != "face" && kind != "joint") || it == names.end()) {
        throw Error("keypoint template '" + keypoint_template.name + "': keypoint '" + k.name +
                    "': anchor '" + a +
                    "' is not face:<coco name>, joint:<coco name> or raised_hip:left|right");
      }
      anchor.index = static_cast<int>(it - names.begin());
    }
    anchor.tolerance_m = static_cast<float>(k.occlusion_tolerance_m);
    anchors.push_back(anchor);
  }
  return anchors;
}

BuiltFrame build_frame(const FrameDraft& draft, const body::BodyData& body_data,
                       const std::vector<motion::SeatedClip>& clips,
                       const std::vector<KeypointAnchor>& anchors,
                       const FurnitureCatalog* furniture) {
  if (draft.people.size() > static_cast<std::size_t>(kMaxPeoplePerFrame))
    throw Error("frame " + std::to_string(draft.index) + ": more than 999 people");
  BuiltFrame built;
  scene::Scene& s = built.scene;
  s.camera = draft.camera;
  s.sun = draft.sun;
  s.point_lights = draft.lights;
  s.environment = draft.sky;
  s.post = draft.post;
  s.background = draft.background;
  s.seed = RandomStream(draft.seed, {"render", static_cast<std::uint64_t>(draft.index)}).next_u64();
  SceneAssembler out(s);
  add_structure(out, draft);
  for (std::size_t i = 0; i < draft.objects.size(); ++i) {
    ObjectDraft o = draft.objects[i];
    const bool model = o.furniture >= 0 && furniture != nullptr &&
                       static_cast<std::size_t>(o.furniture) < furniture->items().size();
    // In rooms objects stand on the floor (unit shapes span y in [-0.5, 0.5], models [0, h]).
    if (draft.environment == EnvironmentKind::kRoom)
      o.position.y() = model ? 0.0f : 0.5f * o.scale.y();
    const int mesh = model ? out.furniture_mesh(*furniture, static_cast<std::size_t>(o.furniture))
                           : out.primitive_mesh(object_spec(o.shape));
    scene::Material m = o.material;
    m.name = "object_" + std::to_string(i + 1);
    out.add_instance(m.name, mesh, out.add_material(m), trs(o.position, o.rotation, o.scale),
                     static_cast<std::uint16_t>(kObjectIdBase + std::min<std::size_t>(i + 1, 999)),
                     kSemanticObject);
  }
  for (std::size_t i = 0; i < draft.empty_chairs.size(); ++i) {
    const EmptyChairDraft& e = draft.empty_chairs[i];
    RandomStream stream(e.seed, {"empty_wheelchair"});
    const body::Wheelchair chair = body::make_empty_wheelchair(e.type, stream);
    const Eigen::Affine3f to_world =
        Eigen::Translation3f(e.position) * e.rotation * Eigen::Scaling(e.scale);
    add_chair(out, chair, chair_colours(chair, std::nullopt), to_world,
              "empty_wheelchair_" + std::to_string(i + 1),
              static_cast<std::uint16_t>(kEmptyChairIdBase + std::min<std::size_t>(i + 1, 999)));
  }
  built.people.resize(draft.people.size());
  for (std::size_t k = 0; k < draft.people.size(); ++k)
    add_person(out, draft, k, body_data, clips, anchors, built.people[k]);
  return built;
}

}  // namespace wheelpose::generate
