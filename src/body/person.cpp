#include "body/person.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>

#include "body/assets.h"
#include "body/rim_reach.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "motion/seating.h"

namespace wheelpose::body {

namespace fs = std::filesystem;

const std::array<const char*, kCocoCount>& coco_names() {
  static const std::array<const char*, kCocoCount> names = {
      "nose",           "left_eye",   "right_eye",   "left_ear",   "right_ear",   "left_shoulder",
      "right_shoulder", "left_elbow", "right_elbow", "left_wrist", "right_wrist", "left_hip",
      "right_hip",      "left_knee",  "right_knee",  "left_ankle", "right_ankle"};
  return names;
}

namespace {

// The lips' base-mesh vertices from the default rig's weights (see BodyData::lip_vertices).
std::vector<int> load_lip_vertices(const fs::path& weights_path, std::size_t vertex_count) {
  const auto json = nlohmann::json::parse(read_asset(weights_path), nullptr, false);
  if (json.is_discarded() || !json.contains("weights") || !json["weights"].is_object()) {
    throw Error(weights_path.string() + ": no 'weights' object");
  }
  std::vector<float> weight(vertex_count, 0.0f);
  for (const auto& [bone, list] : json["weights"].items()) {
    if (!bone.starts_with("oris")) continue;
    try {
      for (const auto& entry : list) {
        const auto v = entry.at(0).get<std::int64_t>();
        if (v < 0 || static_cast<std::size_t>(v) >= vertex_count) {
          throw Error(weights_path.string() + ": bone '" + bone + "' weights vertex " +
                      std::to_string(v) + ", beyond the base mesh");
        }
        weight[static_cast<std::size_t>(v)] += entry.at(1).get<float>();
      }
    } catch (const nlohmann::json::exception& e) {
      throw Error(weights_path.string() + ": bone '" + bone + "': " + e.what());
    }
  }
  std::vector<int> lips;
  for (std::size_t v = 0; v < vertex_count; ++v) {
    if (weight[v] >= 0.5f) lips.push_back(static_cast<int>(v));
  }
  if (lips.empty()) throw Error(weights_path.string() + ": no orbicularis oris (oris*) weights");
  return lips;
}

Eigen::Vector3f group_mean(const BaseMesh& base, const std::string& group) {
  const auto it = base.group_vertices.find(group);
  if (it == base.group_vertices.end()) throw Error("base.obj: group '" + group + "' missing");
  Eigen::Vector3f sum = Eigen::Vector3f::Zero();
  for (int v : it->second) sum += base.vertices[v];
  return sum / static_cast<float>(it->second.size());
}

}  // namespace

BodyData::BodyData(const fs::path& assets_root)
    : model_(assets_root), rig_(load_rig(model_.root(), model_.base())), proxies_(model_.root()) {
  const BaseMesh& base = model_.base();
  std::set<int> used;
  for (const auto& q : base.body_quads) used.insert(q.begin(), q.end());
  body_vertices_.assign(used.begin(), used.end());
  std::vector<int> local(base.vertices.size(), -1);
  for (std::size_t i = 0; i < body_vertices_.size(); ++i)
    local[body_vertices_[i]] = static_cast<int>(i);
  for (const auto& q : base.body_quads) {
    const unsigned a = local[q[0]], b = local[q[1]], c = local[q[2]], d = local[q[3]];
    triangles_.push_back({a, b, c});
    if (q[3] != q[0]) triangles_.push_back({a, c, d});
  }
  // Face landmarks on the rest base mesh (decimetres): the nose tip is the most forward midline
  // head vertex; eyes are the eyeball helpers; ears the outermost head vertices behind the eyes.
  const Eigen::Vector3f head = group_mean(base, "joint-head");
  const Eigen::Vector3f eye_l = group_mean(base, "helper-l-eye");
  const Eigen::Vector3f eye_r = group_mean(base, "helper-r-eye");
  int nose = -1, ear_l = -1, ear_r = -1;
  std::vector<int> ear_band;  // head vertices level with and behind the eyes, ascending
  for (int v : body_vertices_) {
    const Eigen::Vector3f& p = base.vertices[v];
    if (p.y() < head.y()) continue;
    if (std::abs(p.x()) < 0.05f && (nose < 0 || p.z() > base.vertices[nose].z())) nose = v;
    if (p.y() <= eye_l.y() - 0.6f || p.y() >= eye_l.y() + 0.1f || p.z() >= eye_l.z() - 0.6f)
      continue;
    ear_band.push_back(v);
    if (ear_l < 0 || p.x() > base.vertices[ear_l].x()) ear_l = v;
    if (ear_r < 0 || p.x() < base.vertices[ear_r].x()) ear_r = v;
  }
  if (nose < 0 || ear_l < 0 || ear_r < 0) throw Error("base.obj: head landmarks not found");
  // The ear stands out of the skull: its band vertices within 0.2 dm of the outermost one are
  // the ear itself, and their mean is its centre.
  for (int v : ear_band) {
    if (base.vertices[v].x() > base.vertices[ear_l].x() - 0.2f) ear_centres_[0].push_back(v);
    if (base.vertices[v].x() < base.vertices[ear_r].x() + 0.2f) ear_centres_[1].push_back(v);
  }
  face_[0] = {nose};
  face_[1] = base.group_vertices.at("helper-l-eye");
  face_[2] = base.group_vertices.at("helper-r-eye");
  face_[3] = {ear_l};
  face_[4] = {ear_r};
  (void)eye_r;
  lips_ = load_lip_vertices(model_.root() / "rigs" / "default_weights.mhw", base.vertices.size());
}

PersonSpec sample_spec(std::uint64_t seed) {
  PersonSpec spec;
  spec.seed = seed;
  RandomStream s(seed, {"body", "params"});
  MacroParams& p = spec.params;
  p.gender = s.uniform01();
  p.age_years = s.bernoulli(0.12) ? s.uniform(10, 18) : s.uniform(18, 90);
  p.muscle = std::clamp(s.normal(0.5, 0.18), 0.0, 1.0);
  p.weight = std::clamp(s.normal(0.5, 0.2), 0.0, 1.0);
  p.height = std::clamp(s.normal(0.5, 0.2), 0.0, 1.0);
  p.proportions = s.uniform(0.3, 0.9);
  // A mix of ancestries, usually dominated by one.
  const double a = std::pow(s.uniform01(), 3), b = std::pow(s.uniform01(), 3),
               c = std::pow(s.uniform01(), 3);
  const double sum = std::max(a + b + c, 1e-9);
  p.african = a / sum;
  p.asian = b / sum;
  p.caucasian = c / sum;
  const double tone = 0.12 * p.african + 0.6 * p.asian + 0.8 * p.caucasian;
  p.skin_tone = std::clamp(tone + s.normal(0.0, 0.1), 0.0, 1.0);
  // About one person in sixteen has a limb difference.
  if (s.bernoulli(1.0 / 16)) {
    const int limb = static_cast<int>(s.uniform_int(0, 3));
    spec.limbs[limb] = s.bernoulli(0.5) ? Cut::kBelow : Cut::kAbove;
  }
  const double u = s.uniform01();
  spec.wheelchair = u < 0.6    ? WheelchairType::kManual
                    : u < 0.75 ? WheelchairType::kSport
                               : WheelchairType::kPower;
  return spec;
}

void apply_overrides(PersonSpec& spec, const std::vector<std::string>& overrides) {
  for (const std::string& kv : overrides) {
    const auto eq = kv.find('=');
    if (eq == std::string::npos) throw Error("--params " + kv + ": expected key=value");
    const std::string key = kv.substr(0, eq), value = kv.substr(eq + 1);
    if (key == "wheelchair") {
      spec.wheelchair = wheelchair_type_from_name(value);
    } else if (key == "hands_on_rims") {
      if (value != "0" && value != "1")
        throw Error("--params hands_on_rims=" + value + ": expected 0 or 1");
      spec.hands_on_rims = value == "1";
    } else if (key == "wear") {
      spec.proxies.push_back(value);
    } else if (key == "mobility_aid") {
      spec.mobility_aid = mobility_aid_from_name(value);
    } else if (key.ends_with("_leg") || key.ends_with("_arm")) {
      const Limb limb = limb_from_name(key);
      spec.limbs[static_cast<int>(limb)] = cut_from_name(limb, value);
    } else {
      spec.params.set(key, value);
    }
  }
}

motion::PoseRotations rest_seated_pose() {
  using Q = Eigen::Quaterniond;
  using V = Eigen::Vector3d;
  motion::PoseRotations g;
  g.fill(Q::Identity());
  const motion::SeatingOptions seat;
  const V down(0, -1, 0);
  for (int hip : {motion::kLeftHip, motion::kRightHip}) {
    g[hip] = Q::FromTwoVectors(down, motion::seated_thigh_direction(seat));
  }
  for (int knee : {motion::kLeftKnee, motion::kRightKnee}) {
    g[knee] = Q::FromTwoVectors(down, motion::seated_shin_direction(seat));
  }
  for (int side : {1, -1}) {
    const bool left = side > 0;
    const int shoulder = left ? motion::kLeftShoulder : motion::kRightShoulder;
    const int elbow = left ? motion::kLeftElbow : motion::kRightElbow;
    const int wrist = left ? motion::kLeftWrist : motion::kRightWrist;
    const V rest(side, 0, 0);
    g[shoulder] = Q::FromTwoVectors(rest, V(0.08 * side, -0.95, 0.3).normalized());
    g[elbow] = Q::FromTwoVectors(rest, V(-0.2 * side, 0.2, 0.96).normalized());
    g[wrist] = g[elbow];
  }
  return g;
}

motion::PoseRotations rest_standing_pose() {
  using Q = Eigen::Quaterniond;
  using V = Eigen::Vector3d;
  motion::PoseRotations g;
  g.fill(Q::Identity());
  for (int side : {1, -1}) {
    const bool left = side > 0;
    const Q arm_down = Q::FromTwoVectors(V(side, 0, 0), V(0.15 * side, -0.99, 0).normalized());
    for (int joint :
         left ? std::array{motion::kLeftShoulder, motion::kLeftElbow, motion::kLeftWrist}
              : std::array{motion::kRightShoulder, motion::kRightElbow, motion::kRightWrist})
      g[joint] = arm_down;
  }
  return g;
}

motion::PoseRotations with_standing_legs(motion::PoseRotations pose) {
  // The pelvis's heading (its forward +Z turned about the vertical): the legs keep facing where
  // the body faces, straight down, feet flat.
  const Eigen::Vector3d forward = pose[motion::kPelvis] * Eigen::Vector3d::UnitZ();
  const double heading = std::atan2(forward.x(), forward.z());
  const Eigen::Quaterniond legs(Eigen::AngleAxisd(heading, Eigen::Vector3d::UnitY()));
  for (int joint : {motion::kLeftHip, motion::kRightHip, motion::kLeftKnee, motion::kRightKnee,
                    motion::kLeftAnkle, motion::kRightAnkle, motion::kLeftToe, motion::kRightToe})
    pose[joint] = legs;
  return pose;
}

namespace {

// The rig pose of the spec's frame, the chair fitted to the body (none when standing) and the
// posed morphed vertices.
struct Seated {
  RigPose pose;
  std::vector<Eigen::Vector3f> posed;
};

Seated seat(const BodyData& data, const PersonSpec& spec,
            const std::vector<Eigen::Vector3f>& morphed, Person& person) {
  const Rig& rig = data.rig();
  const bool standing = spec.wheelchair == WheelchairType::kNone;
  Seated out;
  out.pose = retarget(rig, person.rest_bones,
                      standing ? with_standing_legs(spec.pose ? *spec.pose : rest_standing_pose())
                      : spec.pose ? *spec.pose
                                  : rest_seated_pose());
  if (standing) {
    RandomStream no_chair(spec.seed, {"body", "wheelchair"});
    person.chair = make_wheelchair(WheelchairType::kNone, SeatFit{}, no_chair);
    out.posed = skin(rig, person.rest_bones, out.pose, morphed);
    return out;
  }
  // The chair is fitted to the rest seated pose, so it does not change with the clip frame.
  const RigPose seated =
      spec.pose ? retarget(rig, person.rest_bones, rest_seated_pose()) : out.pose;
  std::vector<Eigen::Vector3f> seated_vertices = skin(rig, person.rest_bones, seated, morphed);
  const motion::Pose seated_joints =
      skeleton_joints(rig, pose_bones(rig, person.rest_bones, seated));
  const SeatFit fit = measure_seat_fit(seated_vertices, data.body_vertices(),
                                       seated_joints[motion::kLeftHip].cast<float>(),
                                       seated_joints[motion::kRightHip].cast<float>(),
                                       seated_joints[motion::kLeftKnee].cast<float>(),
                                       seated_joints[motion::kLeftAnkle].cast<float>(),
                                       seated_joints[motion::kHeadBase].cast<float>());
  RandomStream chair_stream(spec.seed, {"body", "wheelchair"});
  person.chair = make_wheelchair(spec.wheelchair, fit, chair_stream,
                                 ChairOptions{.headrest = spec.chair_headrest.value_or(true)});
  // Pushing clips: the hands go to the rims (the chair is in the same, unshifted frame).
  const bool on_rims =
      spec.hands_on_rims && reach_push_rims(rig, person.rest_bones, person.chair, out.pose) > 0;
  out.posed = spec.pose || on_rims ? skin(rig, person.rest_bones, out.pose, morphed)
                                   : std::move(seated_vertices);
  return out;
}

// The worn proxies, the base vertices they cover (hidden so skin does not poke through) and the
// base vertices (helpers included: clothes are fitted to the helper tights) beyond a limb cut.
struct Wardrobe {
  std::vector<const Proxy*> worn;
  std::vector<bool> covered, removed_base;
};

Wardrobe wardrobe(const BodyData& data, const PersonSpec& spec,
                  const std::vector<Eigen::Vector3f>& morphed, const BoneFrames& rest_bones) {
  Wardrobe out;
  out.covered.assign(morphed.size(), false);
  out.removed_base.assign(morphed.size(), false);
  for (const std::string& name : spec.proxies) {
    out.worn.push_back(&data.proxies().get(name));
    for (int v : out.worn.back()->delete_verts)
      if (v >= 0 && static_cast<std::size_t>(v) < out.covered.size()) out.covered[v] = true;
  }
  if (!out.worn.empty() &&
      std::any_of(spec.limbs.begin(), spec.limbs.end(), [](Cut c) { return c != Cut::kNone; })) {
    std::vector<int> all(morphed.size());
    for (std::size_t v = 0; v < all.size(); ++v) all[v] = static_cast<int>(v);
    const std::vector<int> limb_of =
        limbs_beyond_cuts(data.rig(), rest_bones, morphed, all, spec.limbs);
    for (std::size_t v = 0; v < all.size(); ++v) out.removed_base[v] = limb_of[v] >= 0;
  }
  return out;
}

// The visible body: the base mesh without what the limb cuts remove or clothes cover, with the
// cap centres (their rims' means) after the kept vertices.
void add_cut_body(const BodyData& data, const PersonSpec& spec,
                  const std::vector<Eigen::Vector3f>& morphed,
                  const std::vector<Eigen::Vector3f>& posed, const std::vector<bool>& covered,
                  Person& person) {
  const std::vector<int>& body = data.body_vertices();
  std::vector<Eigen::Vector3f> rest_body;
  rest_body.reserve(body.size());
  for (int v : body) rest_body.push_back(morphed[v]);
  const CutResult cut =
      cut_limbs(data.rig(), person.rest_bones, rest_body, body, data.body_triangles(), spec.limbs);
  // Keep the referenced vertices only, then the cap centres (rim means).
  std::vector<unsigned> remap(body.size() + cut.caps.size(), 0);
  for (std::size_t i = 0; i < body.size(); ++i) {
    if (cut.removed[i]) continue;
    remap[i] = static_cast<unsigned>(person.vertices.size());
    person.vertices.push_back(posed[body[i]]);
    person.rest_vertices.push_back(morphed[body[i]]);
    person.base_vertex.push_back(body[i]);
  }
  for (std::size_t c = 0; c < cut.caps.size(); ++c) {
    Eigen::Vector3f p = Eigen::Vector3f::Zero(), r = Eigen::Vector3f::Zero();
    for (unsigned v : cut.cap_rims[c]) {
      p += posed[body[v]];
      r += morphed[body[v]];
    }
    const float n = static_cast<float>(cut.cap_rims[c].size());
    remap[cut.caps[c]] = static_cast<unsigned>(person.vertices.size());
    person.vertices.push_back(p / n);
    person.rest_vertices.push_back(r / n);
    person.base_vertex.push_back(-1);
    std::vector<unsigned>& rim = person.cap_rims.emplace_back();
    for (unsigned v : cut.cap_rims[c]) rim.push_back(remap[v]);
  }
  const std::vector<int>& lips = data.lip_vertices();
  person.lips.resize(person.base_vertex.size(), 0);
  for (std::size_t v = 0; v < person.base_vertex.size(); ++v) {
    const int base = person.base_vertex[v];
    person.lips[v] = base >= 0 && std::binary_search(lips.begin(), lips.end(), base) ? 1 : 0;
  }
  person.triangles.reserve(cut.triangles.size());
  auto hidden = [&](unsigned local) { return local < body.size() && covered[body[local]]; };
  for (const auto& t : cut.triangles) {
    if (hidden(t[0]) || hidden(t[1]) || hidden(t[2])) continue;
    person.triangles.push_back({remap[t[0]], remap[t[1]], remap[t[2]]});
  }
}

// Each worn proxy fitted to the posed and to the rest body, without faces on a removed limb.
void dress(const Wardrobe& wardrobe, const std::vector<Eigen::Vector3f>& morphed,
           const std::vector<Eigen::Vector3f>& posed, Person& person) {
  for (const Proxy* proxy : wardrobe.worn) {
    Garment g;
    g.name = proxy->name;
    g.vertices = fit_proxy(*proxy, morphed, posed);
    g.rest_vertices = fit_proxy(*proxy, morphed, morphed);
    for (const auto& t : proxy->triangles) {
      bool on_removed_limb = false;
      for (unsigned c : t)
        for (int r : proxy->refs[c]) on_removed_limb = on_removed_limb || wardrobe.removed_base[r];
      if (!on_removed_limb) g.triangles.push_back(t);
    }
    person.garments.push_back(std::move(g));
  }
}

// Our joint behind each COCO keypoint (-1 for the face, which follows the head bone).
constexpr int kCocoJoint[kCocoCount] = {-1,
                                        -1,
                                        -1,
                                        -1,
                                        -1,
                                        motion::kLeftShoulder,
                                        motion::kRightShoulder,
                                        motion::kLeftElbow,
                                        motion::kRightElbow,
                                        motion::kLeftWrist,
                                        motion::kRightWrist,
                                        motion::kLeftHip,
                                        motion::kRightHip,
                                        motion::kLeftKnee,
                                        motion::kRightKnee,
                                        motion::kLeftAnkle,
                                        motion::kRightAnkle};

// The 23 joints, COCO-17 keypoints (the face's moving rigidly with the head bone), which of
// them a limb cut removes, and where COCO's annotators would put them (Person::annotated).
void place_keypoints(const BodyData& data, const PersonSpec& spec,
                     const std::vector<Eigen::Vector3f>& morphed, const RigPose& pose,
                     Person& person) {
  const Rig& rig = data.rig();
  person.joints = skeleton_joints(rig, person.posed_bones);
  const int head = rig.bone("head");
  const Eigen::Quaternionf head_rot = pose.rotation[head];
  // The mean of some head vertices at rest, carried rigidly with the head bone.
  const auto on_head = [&](const std::vector<int>& vertices) {
    Eigen::Vector3f sum = Eigen::Vector3f::Zero();
    for (int v : vertices) sum += morphed[v];
    const Eigen::Vector3f rest = sum / static_cast<float>(vertices.size());
    return Eigen::Vector3f(person.posed_bones.head[head] +
                           head_rot * (rest - person.rest_bones.head[head]));
  };
  for (int k = 0; k < kCocoCount; ++k) {
    person.coco[k] = kCocoJoint[k] >= 0 ? person.joints[kCocoJoint[k]].cast<float>().eval()
                                        : on_head(data.face_landmarks()[k]);
  }
  const std::vector<int> absent = absent_joints(spec.limbs);
  for (int k = 0; k < kCocoCount; ++k) {
    person.coco_present[k] =
        kCocoJoint[k] < 0 || std::find(absent.begin(), absent.end(), kCocoJoint[k]) == absent.end();
  }
  const Eigen::Vector3f up = (person.joints[motion::kNeckBase] - person.joints[motion::kPelvis])
                                 .cast<float>()
                                 .normalized();
  person.annotated = person.coco;
  for (int k : {5, 6}) person.annotated[k] += kAnnotatedShoulderRaise * up;
  for (int k : {11, 12}) person.annotated[k] += kAnnotatedHipRaise * up;
  for (int side = 0; side < 2; ++side)
    person.annotated[3 + side] = on_head(data.ear_centres()[side]);
}

// Moves everything posed so that the floor is at y = 0: under the chair, or under the lowest
// point of a standing person.
void stand_on_floor(bool standing, Person& person) {
  float floor_y = person.chair.ground_y;
  if (standing) {
    floor_y = std::numeric_limits<float>::max();
    for (const auto& v : person.vertices) floor_y = std::min(floor_y, v.y());
    for (const auto& g : person.garments)
      for (const auto& v : g.vertices) floor_y = std::min(floor_y, v.y());
  }
  const Eigen::Vector3f shift(0, -floor_y, 0);
  for (auto& v : person.vertices) v += shift;
  for (auto& g : person.garments)
    for (auto& v : g.vertices) v += shift;
  for (auto& j : person.joints) j += shift.cast<double>();
  for (auto& k : person.coco) k += shift;
  for (auto& k : person.annotated) k += shift;
  for (auto& h : person.posed_bones.head) h += shift;
  for (auto& t : person.posed_bones.tail) t += shift;
  for (auto& p : person.chair.parts) p.centre += shift;
  for (auto& v : person.chair.model.vertices) v += shift;
  person.chair.ground_y = 0;
  person.pose.root_offset += shift;
}

// The mobility aid at the floor-level body's hands and knees.
void place_aid(const PersonSpec& spec, Person& person) {
  if (spec.mobility_aid == MobilityAidType::kNone) return;
  AidAnchors anchors{person.coco[7],  person.coco[8],  person.coco[9],
                     person.coco[10], person.coco[13], person.coco[14]};
  anchors.left_hand = person.coco_present[9];
  anchors.right_hand = person.coco_present[10];
  RandomStream aid_stream(spec.seed, {"body", "mobility_aid"});
  person.aid = make_mobility_aid(spec.mobility_aid, anchors, aid_stream);
}

// Person::description: parameters, chair, keypoints and joints, coordinates to 10 µm.
nlohmann::ordered_json describe(const PersonSpec& spec, const Person& person) {
  float ymin = 1e9f, ymax = -1e9f;
  for (const auto& v : person.rest_vertices) {
    ymin = std::min(ymin, v.y());
    ymax = std::max(ymax, v.y());
  }
  auto vec = [](const Eigen::Vector3f& v) {
    auto r = [](float x) { return std::round(static_cast<double>(x) * 1e5) / 1e5; };
    return nlohmann::ordered_json::array({r(v.x()), r(v.y()), r(v.z())});
  };
  nlohmann::ordered_json d;
  d["format"] = "wheelpose.body";
  d["version"] = 1;
  d["seed"] = spec.seed;
  d["params"] = spec.params.to_json();
  d["stature_m"] = std::round(static_cast<double>(ymax - ymin) * 1e4) / 1e4;
  d["skin_colour"] = vec(person.skin);
  d["rig"] = "mpfb2 game_engine (53 bones)";
  d["wheelchair"] = person.chair.dimensions;
  d["mobility_aid"] = mobility_aid_name(person.aid.type);
  d["proxies"] = spec.proxies;
  nlohmann::ordered_json kp;
  for (int k = 0; k < kCocoCount; ++k) kp[coco_names()[k]] = vec(person.coco[k]);
  d["coco_keypoints"] = kp;
  nlohmann::ordered_json present = nlohmann::ordered_json::array();
  for (int k = 0; k < kCocoCount; ++k) present.push_back(person.coco_present[k]);
  d["coco_present"] = present;
  nlohmann::ordered_json limbs;
  for (int i = 0; i < 4; ++i) {
    limbs[limb_name(static_cast<Limb>(i))] = cut_name(static_cast<Limb>(i), spec.limbs[i]);
  }
  d["limbs"] = limbs;
  nlohmann::ordered_json absent_names = nlohmann::ordered_json::array();
  for (int j : absent_joints(spec.limbs))
    absent_names.push_back(std::string(motion::joint_name(j)));
  d["absent_joints"] = absent_names;
  d["raised_hips"] = {{"left_hip", vec(person.annotated[11])},
                      {"right_hip", vec(person.annotated[12])}};
  nlohmann::ordered_json joints;
  for (int j = 0; j < motion::kJointCount; ++j) {
    joints[std::string(motion::joint_name(j))] = vec(person.joints[j].cast<float>());
  }
  d["joints"] = joints;
  return d;
}

}  // namespace

Person build_person(const BodyData& data, const PersonSpec& spec) {
  Person person;
  const std::vector<Eigen::Vector3f> morphed = data.model().morph(spec.params);
  person.rest_bones = bone_positions(data.rig(), morphed);
  Seated seated = seat(data, spec, morphed, person);
  person.posed_bones = pose_bones(data.rig(), person.rest_bones, seated.pose);
  const Wardrobe worn = wardrobe(data, spec, morphed, person.rest_bones);
  add_cut_body(data, spec, morphed, seated.posed, worn.covered, person);
  dress(worn, morphed, seated.posed, person);
  person.skin = skin_colour(spec.params.skin_tone);
  place_keypoints(data, spec, morphed, seated.pose, person);
  person.pose = std::move(seated.pose);
  stand_on_floor(spec.wheelchair == WheelchairType::kNone, person);
  place_aid(spec, person);
  person.description = describe(spec, person);
  return person;
}

std::vector<Eigen::Vector3f> vertex_normals(const std::vector<Eigen::Vector3f>& v,
                                            const std::vector<std::array<unsigned, 3>>& tris) {
  std::vector<Eigen::Vector3f> n(v.size(), Eigen::Vector3f::Zero());
  for (const auto& t : tris) {
    const Eigen::Vector3f f = (v[t[1]] - v[t[0]]).cross(v[t[2]] - v[t[0]]);
    for (unsigned i : t) n[i] += f;
  }
  for (auto& x : n)
    x = x.squaredNorm() > 0 ? x.normalized().eval() : Eigen::Vector3f::UnitY().eval();
  return n;
}

}  // namespace wheelpose::body
