#pragma once
// A posed person seated in a fitted wheelchair (or, with WheelchairType::kNone, standing on the
// floor without one): the body stage's product. BodyData is the shared,
// read-only model (load once); build_person is the per-person work.

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "body/human.h"
#include "body/limb.h"
#include "body/mobility_aid.h"
#include "body/proxy.h"
#include "body/rig.h"
#include "body/wheelchair.h"
#include "motion/clip.h"

namespace wheelpose::body {

inline constexpr int kCocoCount = 17;
// How far up the torso (neck base minus pelvis) an annotated hip and shoulder lie above their
// joints, metres before the person's scale. Hips: the WheelPose authors' raised hips. Shoulders:
// measured — the pretrained MultiPose, unbiased on real COCO people (within 1 % of a person's
// size), puts shoulders about 6 % of a person's size (about 4 cm) above our shoulder joints on
// renders.
inline constexpr float kAnnotatedHipRaise = 0.09f;
inline constexpr float kAnnotatedShoulderRaise = 0.04f;
// COCO-17 order: nose, left_eye, right_eye, left_ear, right_ear, left/right shoulder, elbow,
// wrist, hip, knee, ankle.
const std::array<const char*, kCocoCount>& coco_names();

class BodyData {
 public:
  explicit BodyData(const std::filesystem::path& assets_root);
  const HumanModel& model() const { return model_; }
  const Rig& rig() const { return rig_; }
  // Clothes, shoes, hair and eyebrow proxies under makehuman/, loaded on first use.
  const ProxyLibrary& proxies() const { return proxies_; }
  // Base-mesh vertices used by the visible body (helper geometry excluded), ascending.
  const std::vector<int>& body_vertices() const { return body_vertices_; }
  // Body triangles indexed into body_vertices().
  const std::vector<std::array<unsigned, 3>>& body_triangles() const { return triangles_; }
  // Head-mesh landmarks: base-mesh vertex sets whose mean is the keypoint.
  const std::array<std::vector<int>, 5>& face_landmarks() const { return face_; }
  // The ears' centres (left, right) as vertex sets: the ear's outer 2 cm. COCO's annotators
  // mark an ear at its middle; face_landmarks() keeps the outermost vertex, the rim's top.
  const std::array<std::vector<int>, 2>& ear_centres() const { return ear_centres_; }
  // Base-mesh vertices of the lips: those the default MakeHuman rig's orbicularis oris bones
  // (oris*) move with a summed weight of at least one half. Ascending.
  const std::vector<int>& lip_vertices() const { return lips_; }

 private:
  HumanModel model_;
  Rig rig_;
  ProxyLibrary proxies_;
  std::vector<int> body_vertices_;
  std::vector<std::array<unsigned, 3>> triangles_;
  std::array<std::vector<int>, 5> face_;
  std::array<std::vector<int>, 2> ear_centres_;
  std::vector<int> lips_;
};

struct PersonSpec {
  MacroParams params;
  WheelchairType wheelchair = WheelchairType::kManual;
  std::uint64_t seed = 0;
  // Clip pose (global joint rotations); the rest seated (or standing) pose when absent. A
  // standing person (kNone) takes the clip's upper body on straight legs (with_standing_legs).
  std::optional<motion::PoseRotations> pose;
  LimbCuts limbs{};  // limb difference, none by default
  MobilityAidType mobility_aid = MobilityAidType::kNone;
  // MakeHuman proxies to wear, as "<folder>/<name>" (e.g. "clothes/male_casualsuit01",
  // "hair/short02"); the body hides the skin they cover.
  std::vector<std::string> proxies;
  // Pushing clips: bend the arms so the wrists meet the push rims (manual and sport chairs).
  bool hands_on_rims = false;
  // A power chair's headrest (ChairOptions::headrest); unset is the default, a headrest, and
  // leaves the labels as they were.
  std::optional<bool> chair_headrest;
};

// Random macro parameters and wheelchair type for `seed` (RandomStream(seed, {"body", ...})).
PersonSpec sample_spec(std::uint64_t seed);
// Applies "k=v" overrides (body parameters, wheelchair=manual|sport|power|cc_by|none,
// left_leg/right_leg=none|below_knee|above_knee, left_arm/right_arm=none|below_elbow|above_elbow,
// mobility_aid=none|cane|crutches|walker, wear=<folder>/<proxy> repeatable,
// hands_on_rims=0|1); throws Error.
void apply_overrides(PersonSpec& spec, const std::vector<std::string>& overrides);

// Rest seated pose: thighs 35 degrees above horizontal, shins down, feet flat, upper arms down,
// forearms forward over the lap.
motion::PoseRotations rest_seated_pose();
// Rest standing pose (WheelchairType::kNone without a clip): legs straight, arms down.
motion::PoseRotations rest_standing_pose();
// `pose` with straight legs under the pelvis, feet flat and facing the pelvis's heading: how a
// person without a wheelchair plays a seated clip (the library's clips are authored seated).
motion::PoseRotations with_standing_legs(motion::PoseRotations pose);

// One worn proxy fitted to the posed body.
struct Garment {
  std::string name;                                // "<folder>/<name>"
  std::vector<Eigen::Vector3f> vertices;           // posed, metres
  std::vector<Eigen::Vector3f> rest_vertices;      // fitted to the unposed body (for UVs)
  std::vector<std::array<unsigned, 3>> triangles;  // without faces on a removed limb
};

struct Person {
  std::vector<Eigen::Vector3f> vertices;           // posed visible body vertices, metres
  std::vector<Eigen::Vector3f> rest_vertices;      // the same, morphed and unposed
  std::vector<std::array<unsigned, 3>> triangles;  // over `vertices` (capped after limb cuts)
  BoneFrames rest_bones, posed_bones;
  // The rig pose that gives posed_bones (root_offset includes the floor shift): skinning
  // rest_vertices with it gives `vertices` (cap centres: the mean of their rims).
  RigPose pose;
  std::vector<int> base_vertex;  // per vertex: its base-mesh vertex, -1 for a cap centre
  std::vector<char> lips;        // per vertex: 1 on the lips (BodyData::lip_vertices)
  // Per cap centre (they follow the body's vertices, in order): the vertices it is the mean of.
  std::vector<std::vector<unsigned>> cap_rims;
  motion::Pose joints;                           // our 23 joints on the posed body
  std::array<Eigen::Vector3f, kCocoCount> coco;  // COCO-17 keypoints
  std::array<bool, kCocoCount> coco_present{};   // false beyond a limb cut (label v = 0)
  // COCO-17 keypoints where COCO's annotators put them on a photo (the `annotated:` anchors of
  // data/keypoints/coco17-as-annotated.json): hips 9 cm up the torso (the WheelPose authors'
  // raised hips), shoulders kAnnotatedShoulderRaise up the torso (the top of the shoulder, not
  // the joint inside it), ears at the ear's centre; the other points as in `coco`.
  std::array<Eigen::Vector3f, kCocoCount> annotated;
  Eigen::Vector3f skin = Eigen::Vector3f::Ones();
  Wheelchair chair;
  MobilityAid aid;                     // held in the hands (or standing in front), empty when none
  std::vector<Garment> garments;       // in PersonSpec::proxies order
  nlohmann::ordered_json description;  // parameters, chair dimensions, keypoints
};

Person build_person(const BodyData& data, const PersonSpec& spec);

// Area-weighted unit vertex normals of a triangle mesh (+Y where a vertex has no area).
std::vector<Eigen::Vector3f> vertex_normals(const std::vector<Eigen::Vector3f>& vertices,
                                            const std::vector<std::array<unsigned, 3>>& triangles);

}  // namespace wheelpose::body
