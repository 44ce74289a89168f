#pragma once
// Turns a FrameDraft into a renderable Scene (meshes in world space) plus, per person, what the
// labeler needs: the keypoints of the chosen template in world space and the person's
// attributes. Instance ids: person k (0-based) → k + 1 for the body and its garments,
// kChairIdBase + k + 1 for the person's wheelchair, kAidIdBase + k + 1 for their mobility aid;
// empty wheelchairs, objects, statues and the wall/room take ids from their own bases so a person's
// visible mask is its body alone.

#include <cstdint>
#include <nlohmann/json.hpp>
#include <vector>

#include "body/person.h"
#include "core/keypoint_template.h"
#include "generate/frame_draft.h"
#include "generate/furniture.h"
#include "motion/clip.h"
#include "scene/scene.h"

namespace wheelpose::generate {

inline constexpr std::uint16_t kChairIdBase = 1000;
inline constexpr std::uint16_t kEmptyChairIdBase = 2000;
inline constexpr std::uint16_t kObjectIdBase = 3000;
inline constexpr std::uint16_t kStructureIdBase = 4000;
inline constexpr std::uint16_t kAidIdBase = 5000;
inline constexpr std::uint16_t kStatueIdBase = 6000;
inline constexpr int kMaxPeoplePerFrame = 999;

// Semantic classes in the semantic buffer.
enum SemanticClass : std::uint16_t {
  kSemanticPerson = 1,
  kSemanticWheelchair = 2,
  kSemanticObject = 3,
  kSemanticStructure = 4,  // wall, floor, room walls
  kSemanticMobilityAid = 5,
};

struct LabelPerson {
  std::uint16_t instance_id = 0;
  std::vector<Eigen::Vector3f> keypoints;  // world, template order
  std::vector<bool> present;               // false beyond a limb cut
  std::vector<float> tolerance;            // occlusion tolerance (metres, scaled)
  nlohmann::ordered_json attributes;       // body, wheelchair, limbs, motion
};

struct BuiltFrame {
  scene::Scene scene;
  std::vector<LabelPerson> people;
  // Rooms: the world box of every drafted object, those left out around the camera included.
  std::vector<Eigen::AlignedBox3f> room_object_boxes;
};

// Whether a room's frame seen from `other` leaves out the objects it leaves out from `camera`
// (those within 0.3 m of it): then the frame built for one camera is, with the camera
// replaced, the frame built for the other (framing moves the camera without a rebuild).
bool leaves_out_the_same_objects(const BuiltFrame& frame, const Eigen::Vector3f& camera,
                                 const Eigen::Vector3f& other);

// Per keypoint of `keypoint_template`: which point of a body it is. Throws Error naming the
// template and keypoint for an anchor we cannot resolve.
struct KeypointAnchor {
  // kCoco: body::Person::coco (face: and joint: anchors); kAnnotated: Person::annotated
  // (annotated:<name>, and raised_hip:<side>, the annotated hip).
  enum Kind { kCoco, kAnnotated } kind = kCoco;
  int index = 0;          // COCO-17 index
  float tolerance_m = 0;  // occlusion tolerance at scale 1
};
std::vector<KeypointAnchor> resolve_anchors(const KeypointTemplate& keypoint_template);

BuiltFrame build_frame(const FrameDraft& draft, const body::BodyData& body_data,
                       const std::vector<motion::SeatedClip>& clips,
                       const std::vector<KeypointAnchor>& anchors,
                       const FurnitureCatalog* furniture = nullptr);

}  // namespace wheelpose::generate
