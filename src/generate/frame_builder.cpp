// FrameDraft → Scene: people built, dressed and placed by the body stage (body/placed_person.h)
// become instances with the outfit's materials; empty chairs, occluders and the wall or room.

#include "generate/frame_builder.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <bit>
#include <cmath>
#include <map>

#include "body/placed_person.h"
#include "core/error.h"
#include "core/random.h"
#include "scene/primitives.h"

namespace wheelpose::generate {
namespace {

using Eigen::Vector3f;

// A placed body-stage part as a scene mesh named `name`.
scene::Mesh scene_mesh(body::PlacedPart part, const std::string& name) {
  scene::Mesh mesh;
  mesh.name = name;
  mesh.positions = std::move(part.positions);
  mesh.normals = std::move(part.normals);
  mesh.uvs = std::move(part.uvs);
  mesh.triangles = std::move(part.triangles);
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
    const int index =
        add_mesh(scene_mesh(body::placed_mesh(catalog.mesh(item), Eigen::Affine3f::Identity()),
                            catalog.items()[item].name));
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

// The material a placed part wears: the outfit's colour for it, the person's skin, or the part's
// own colour (a person's chair may have chosen colours instead).
scene::Material part_material(const body::PlacedPart& part, const Outfit& outfit,
                              const std::optional<std::array<Vector3f, 4>>& chair_colours) {
  scene::Material material;
  switch (part.paint) {
    case body::Paint::kTop:
      return outfit.top;
    case body::Paint::kBottom:
      return outfit.bottom;
    case body::Paint::kShoes:
      return outfit.shoes;
    case body::Paint::kHair:
      return outfit.hair;
    case body::Paint::kEyes:
      return outfit.eyes;
    case body::Paint::kSkin: {
      // Skin is not one flat colour: a faint blotchy variation, a little redder in places, a
      // few centimetres across (the body's UVs span about 1.7 m).
      material.diffuse = Vector3f::Ones();
      material.texture.kind = scene::TextureKind::kNoise;
      material.texture.color_a = part.colour.cwiseProduct(Vector3f(1.05f, 0.98f, 0.97f));
      material.texture.color_b = part.colour.cwiseProduct(Vector3f(0.93f, 0.93f, 0.95f));
      material.texture.scale = 24.0f;
      material.texture.seed =
          StreamKey::mix(std::bit_cast<std::uint32_t>(part.colour.x()) ^
                         (std::uint64_t{std::bit_cast<std::uint32_t>(part.colour.y())} << 32));
      material.specular = 0.08f;
      material.shininess = 24.0f;
      return material;
    }
    case body::Paint::kLips:
      // Lips are the skin's colour, redder and a little darker (less melanin over more blood),
      // and moist: a tighter highlight.
      material.diffuse = part.colour.cwiseProduct(Vector3f(0.92f, 0.62f, 0.64f));
      material.specular = 0.15f;
      material.shininess = 48.0f;
      return material;
    case body::Paint::kOwnColour:
      break;
  }
  const bool frame = part.material == 0;
  if (part.owner == body::PartOwner::kMobilityAid) {
    material.diffuse = part.colour;
    material.specular = frame ? 0.5f : 0.05f;
    material.shininess = 64.0f;
    return material;
  }
  material.diffuse =
      chair_colours ? (*chair_colours)[static_cast<std::size_t>(part.material)] : part.colour;
  material.specular = frame ? 0.4f : 0.05f;
  material.shininess = frame ? 64.0f : 16.0f;
  return material;
}

// The instance ids of what a person (or an empty chair) is made of.
struct PartIds {
  std::uint16_t body = 0, wheelchair = 0, aid = 0;
};

// Each part as an instance of its own mesh and material, named `prefix`_`part name`; `motions`
// (one per part, or none) become the meshes' Mesh::motion.
void add_parts(SceneAssembler& out, std::vector<body::PlacedPart> parts, const std::string& prefix,
               const PartIds& ids, const Outfit& outfit,
               const std::optional<std::array<Vector3f, 4>>& chair_colours,
               std::vector<std::vector<Vector3f>> motions = {}) {
  for (std::size_t i = 0; i < parts.size(); ++i) {
    body::PlacedPart& part = parts[i];
    const std::string name = prefix + "_" + part.name;
    scene::Material material = part_material(part, outfit, chair_colours);
    material.name = name;
    std::uint16_t id = ids.body, semantic = kSemanticPerson;
    if (part.owner == body::PartOwner::kWheelchair) {
      id = ids.wheelchair;
      semantic = kSemanticWheelchair;
    } else if (part.owner == body::PartOwner::kMobilityAid) {
      id = ids.aid;
      semantic = kSemanticMobilityAid;
    }
    scene::Mesh mesh = scene_mesh(std::move(part), name);
    if (i < motions.size()) mesh.motion = std::move(motions[i]);
    out.add_instance(name, out.add_mesh(std::move(mesh)), out.add_material(material),
                     Eigen::Matrix4f::Identity(), id, semantic);
  }
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

// The clip's frame shown at `time` (seconds).
std::size_t clip_frame(const motion::SeatedClip& clip, double time) {
  const std::size_t count = clip.motion.frame_count();
  const double f = std::floor(time * clip.motion.fps);
  return f <= 0 ? 0 : std::min(count - 1, static_cast<std::size_t>(f));
}

motion::PoseRotations clip_pose(const motion::SeatedClip& clip, double time) {
  return motion::global_rotations(clip.motion, clip_frame(clip, time));
}

// How far each vertex of `parts` travels while the shutter is open: the clip's motion from the
// shown frame to the next (the previous one to it at the clip's end), scaled to the shutter
// time. A part whose mesh differs between the frames stays still.
std::vector<std::vector<Vector3f>> part_motions(const std::vector<body::PlacedPart>& parts,
                                                const body::BodyData& body_data,
                                                body::PersonSpec spec,
                                                const motion::SeatedClip& clip, double time,
                                                float shutter, const body::DressCode& dress,
                                                const Eigen::Affine3f& to_world) {
  const std::size_t frame = clip_frame(clip, time);
  if (clip.motion.frame_count() < 2 || shutter <= 0) return {};
  const bool last = frame + 1 >= clip.motion.frame_count();
  spec.pose = motion::global_rotations(clip.motion, last ? frame - 1 : frame + 1);
  const std::vector<body::PlacedPart> other =
      body::place_person(body::build_person(body_data, spec), body_data.rig(), dress, to_world);
  // Positions per second × the shutter; stepping back to the previous frame flips the sign.
  const float scale = static_cast<float>(shutter * clip.motion.fps) * (last ? -1.0f : 1.0f);
  std::vector<std::vector<Vector3f>> motions(parts.size());
  for (std::size_t i = 0; i < parts.size() && i < other.size(); ++i) {
    const auto& now = parts[i].positions;
    const auto& then = other[i].positions;
    if (other[i].name != parts[i].name || then.size() != now.size()) continue;
    motions[i].resize(now.size());
    for (std::size_t v = 0; v < now.size(); ++v) motions[i][v] = (then[v] - now[v]) * scale;
  }
  return motions;
}

// The person's keypoints in the world and the attributes its annotation records.
void label_person(const body::Person& person, const body::PersonSpec& spec, const PersonDraft& p,
                  const motion::SeatedClip* clip, const Eigen::Affine3f& to_world,
                  const std::vector<KeypointAnchor>& anchors, std::uint16_t id,
                  LabelPerson& label) {
  label.instance_id = id;
  for (const KeypointAnchor& a : anchors) {
    const bool annotated = a.kind == KeypointAnchor::kAnnotated;
    const Vector3f local = annotated ? person.annotated[a.index] : person.coco[a.index];
    label.keypoints.push_back(to_world * local);
    label.tolerance.push_back(a.tolerance_m * p.scale);
    label.present.push_back(person.coco_present[a.index]);
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
  if (spec.chair_headrest && person.chair.type == body::WheelchairType::kPower) {
    label.attributes["power_chair_headrest"] = *spec.chair_headrest;
  }
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

// World = position + rotation · (scale · (p − anchor)), where anchor is the pelvis over the
// floor (x, z) at floor height 0 in rooms (so the wheels or feet stay on the floor), the pelvis
// itself in the wall layout.
Eigen::Affine3f placement(const body::Person& person, const FrameDraft& draft,
                          const Vector3f& position, const Eigen::Quaternionf& rotation,
                          float scale) {
  const Vector3f pelvis = person.joints[motion::kPelvis].cast<float>();
  const Vector3f anchor(pelvis.x(), draft.environment == EnvironmentKind::kRoom ? 0.0f : pelvis.y(),
                        pelvis.z());
  return Eigen::Translation3f(position) * rotation * Eigen::Scaling(scale) *
         Eigen::Translation3f(-anchor);
}

// A statue: the posed body in one material, an object to the labels.
void add_statue(SceneAssembler& out, const FrameDraft& draft, std::size_t i,
                const body::BodyData& body_data, const std::vector<motion::SeatedClip>& clips) {
  const StatueDraft& statue = draft.statues[i];
  body::PersonSpec spec = statue.spec;
  if (statue.clip >= 0 && static_cast<std::size_t>(statue.clip) < clips.size())
    spec.pose = clip_pose(clips[statue.clip], statue.time);
  const body::Person person = body::build_person(body_data, spec);
  const Eigen::Affine3f to_world =
      placement(person, draft, statue.position, statue.rotation, statue.scale);
  const std::string prefix = "statue_" + std::to_string(i + 1);
  const auto id = static_cast<std::uint16_t>(kStatueIdBase + std::min<std::size_t>(i + 1, 999));
  for (body::PlacedPart& part : body::place_person(person, body_data.rig(), {}, to_world)) {
    const std::string name = prefix + "_" + part.name;
    scene::Material material = statue.material;
    material.name = name;
    out.add_instance(name, out.add_mesh(scene_mesh(std::move(part), name)),
                     out.add_material(material), Eigen::Matrix4f::Identity(), id, kSemanticObject);
  }
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
  const Eigen::Affine3f to_world = placement(person, draft, p.position, p.rotation, p.scale);
  const body::DressCode dress{p.outfit.long_sleeves, p.outfit.long_trousers};
  const PartIds ids{static_cast<std::uint16_t>(k + 1),
                    static_cast<std::uint16_t>(kChairIdBase + k + 1),
                    static_cast<std::uint16_t>(kAidIdBase + k + 1)};
  std::vector<body::PlacedPart> parts =
      body::place_person(person, body_data.rig(), dress, to_world);
  std::vector<std::vector<Vector3f>> motions;
  if (clip != nullptr && draft.shutter > 0)
    motions = part_motions(parts, body_data, spec, *clip, p.time, draft.shutter, dress, to_world);
  add_parts(out, std::move(parts), "person_" + std::to_string(k + 1), ids, p.outfit,
            p.chair_colours, std::move(motions));
  label_person(person, spec, p, clip, to_world, anchors, ids.body, label);
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
  if (draft.room.outdoor) {
    const float half = kOutdoorGroundSize / 2;
    plane("ground", half, half, draft.room.floor, Vector3f::Zero(), Eigen::Quaternionf::Identity());
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
      anchor.kind = KeypointAnchor::kAnnotated;
      anchor.index = what == "left" ? 11 : 12;
    } else {
      const auto& names = body::coco_names();
      const auto it = std::find(names.begin(), names.end(), what);
      if ((kind != "face" && kind != "joint" && kind != "annotated") || it == names.end()) {
        throw Error("keypoint template '" + keypoint_template.name + "': keypoint '" + k.name +
                    "': anchor '" + a +
                    "' is not face:<coco name>, joint:<coco name>, annotated:<coco name> or "
                    "raised_hip:left|right");
      }
      if (kind == "annotated") anchor.kind = KeypointAnchor::kAnnotated;
      anchor.index = static_cast<int>(it - names.begin());
    }
    anchor.tolerance_m = static_cast<float>(k.occlusion_tolerance_m);
    anchors.push_back(anchor);
  }
  return anchors;
}

namespace {

Eigen::AlignedBox3f world_box(const scene::Mesh& mesh, const Eigen::Matrix4f& transform) {
  Eigen::AlignedBox3f box;
  for (const Vector3f& v : mesh.positions) box.extend((transform * v.homogeneous()).head<3>());
  return box;
}

// Whether `camera` stands within kCameraClearance of an object's box.
bool near_the_camera(const Eigen::AlignedBox3f& box, const Vector3f& camera) {
  constexpr float kCameraClearance = 0.3f;  // metres
  return !box.isEmpty() && box.exteriorDistance(camera) < kCameraClearance;
}

}  // namespace

bool leaves_out_the_same_objects(const BuiltFrame& frame, const Vector3f& camera,
                                 const Vector3f& other) {
  for (const Eigen::AlignedBox3f& box : frame.room_object_boxes) {
    if (near_the_camera(box, camera) != near_the_camera(box, other)) return false;
  }
  return true;
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
    if (draft.environment == EnvironmentKind::kRoom) {
      o.position.y() = model ? furniture->items()[static_cast<std::size_t>(o.furniture)].elevation
                             : 0.5f * o.scale.y();
    }
    const int mesh = model ? out.furniture_mesh(*furniture, static_cast<std::size_t>(o.furniture))
                           : out.primitive_mesh(object_spec(o.shape));
    const Eigen::Matrix4f transform = trs(o.position, o.rotation, o.scale);
    // A room's camera stands near a wall, where furniture stands too: an object around
    // the camera would fill the frame (2.5 % of the realistic scenario's frames were black, the
    // camera inside a wardrobe), so it is left out.
    if (draft.environment == EnvironmentKind::kRoom) {
      built.room_object_boxes.push_back(
          world_box(s.meshes[static_cast<std::size_t>(mesh)], transform));
      if (near_the_camera(built.room_object_boxes.back(), s.camera.position)) continue;
    }
    scene::Material m = o.material;
    m.name = "object_" + std::to_string(i + 1);
    out.add_instance(m.name, mesh, out.add_material(m), transform,
                     static_cast<std::uint16_t>(kObjectIdBase + std::min<std::size_t>(i + 1, 999)),
                     kSemanticObject);
  }
  for (std::size_t i = 0; i < draft.empty_chairs.size(); ++i) {
    const EmptyChairDraft& e = draft.empty_chairs[i];
    RandomStream stream(e.seed, {"empty_wheelchair"});
    const body::Wheelchair chair = body::make_empty_wheelchair(e.type, stream);
    const Eigen::Affine3f to_world =
        Eigen::Translation3f(e.position) * e.rotation * Eigen::Scaling(e.scale);
    const PartIds ids{
        0, static_cast<std::uint16_t>(kEmptyChairIdBase + std::min<std::size_t>(i + 1, 999))};
    add_parts(out, body::place_wheelchair(chair, to_world),
              "empty_wheelchair_" + std::to_string(i + 1), ids, Outfit{}, e.colours);
  }
  for (std::size_t i = 0; i < draft.statues.size(); ++i)
    add_statue(out, draft, i, body_data, clips);
  built.people.resize(draft.people.size());
  for (std::size_t k = 0; k < draft.people.size(); ++k)
    add_person(out, draft, k, body_data, clips, anchors, built.people[k]);
  return built;
}

}  // namespace wheelpose::generate
