#pragma once
// What the randomizers decide for one frame, as plain data and before any mesh exists. The frame
// builder (frame_builder.h) turns a draft into a renderable Scene plus the people to label.

#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "body/person.h"
#include "scene/scene.h"

namespace wheelpose::generate {

enum class EnvironmentKind { kWall, kRoom };

// A background occluder, or a piece of furniture in a room: a primitive or a loaded model.
struct ObjectDraft {
  std::string shape = "box";  // "box", "sphere", "capsule", "cylinder"
  int furniture = -1;  // index into the furniture catalog (rooms); -1 = the primitive `shape`
  Eigen::Vector3f position = Eigen::Vector3f::Zero();
  Eigen::Quaternionf rotation = Eigen::Quaternionf::Identity();
  Eigen::Vector3f scale = Eigen::Vector3f::Ones();  // multiplies a unit-sized shape (1 m)
  scene::Material material;
};

// Garment colours and patterns of one person (the body mesh is split by nearest bone).
struct Outfit {
  scene::Material top, bottom, shoes, hair, eyes;  // hair: the hair's and the eyebrows'
  bool long_sleeves = true;
  bool long_trousers = true;
};

// Makes `hair` MakeHuman's alpha cards of strands (render/strands.h), `coverage` of each card
// layer: 150 strands per UV unit are ~2 per cm at the hair proxies' UV scale.
inline void cut_into_strands(scene::Material& hair, float coverage) {
  hair.strands_per_uv = 150.0f;
  hair.strand_coverage = coverage;
}

struct PersonDraft {
  int pool_slot = 0;  // which person of the current pool
  body::PersonSpec spec;
  Outfit outfit;
  int clip = -1;      // index into the motion clips; -1 = rest seated pose
  double time = 0.0;  // seconds into the clip
  std::optional<std::array<Eigen::Vector3f, 4>> chair_colours;  // frame, upholstery, tyre, trim
  // Placement: world = position + rotation · (scale · (p − anchor)), where anchor is the
  // person's pelvis over the floor (x, z) at floor height 0 — so scale keeps the wheels on the
  // floor in rooms and the pelvis at `position` on the wall layout (see frame_builder.cpp).
  Eigen::Vector3f position = Eigen::Vector3f::Zero();
  Eigen::Quaternionf rotation = Eigen::Quaternionf::Identity();
  float scale = 1.0f;
  bool placed = false;  // a placement randomizer has set the transform
};

struct EmptyChairDraft {
  body::WheelchairType type = body::WheelchairType::kManual;
  std::uint64_t seed = 0;
  Eigen::Vector3f position = Eigen::Vector3f::Zero();
  Eigen::Quaternionf rotation = Eigen::Quaternionf::Identity();
  float scale = 1.0f;
  std::optional<std::array<Eigen::Vector3f, 4>> colours;  // else the chair's own draw
};

// A statue or a mannequin: a posed body of one material (stone, bronze, plaster), bare and
// bald, unlabelled: a human shape a model must learn is not a person.
struct StatueDraft {
  body::PersonSpec spec;  // standing (WheelchairType::kNone), no proxies
  int clip = -1;          // index into the motion clips; -1 = the rest pose
  double time = 0.0;
  Eigen::Vector3f position = Eigen::Vector3f::Zero();
  Eigen::Quaternionf rotation = Eigen::Quaternionf::Identity();
  float scale = 1.0f;
  scene::Material material;
};

struct RoomDraft {
  Eigen::Vector2f size = Eigen::Vector2f(8.0f, 8.0f);  // floor x, z extent (metres)
  float height = 2.8f;
  scene::Material floor, walls;
  // Outdoors: the same layout on open ground (kOutdoorGroundSize across) under the sky, with
  // no walls or ceiling; `floor` is the ground.
  bool outdoor = false;
};
// Metres: wide enough that the ground's far edge sits within half a degree of the sky's horizon.
inline constexpr float kOutdoorGroundSize = 400.0f;

struct FrameDraft {
  std::int64_t index = 0;  // global frame index
  std::uint64_t seed = 0;  // scenario seed
  EnvironmentKind environment = EnvironmentKind::kWall;
  RoomDraft room;
  scene::Material wall;  // the textured wall behind everything (wall layout)
  float wall_z = -10.0f;
  scene::Camera camera;
  // The authors sampled a focal length that did not drive projection (the FOV did); kept as
  // metadata only.
  float nominal_focal_length_mm = 0.0f;
  scene::Sun sun;
  std::vector<scene::PointLight> lights;
  std::optional<scene::Environment> sky;
  scene::PostProcess post;
  scene::Background background;
  std::vector<ObjectDraft> objects;
  std::vector<PersonDraft> people;
  std::vector<EmptyChairDraft> empty_chairs;
  std::vector<StatueDraft> statues;
  // How the image is written: JPEG quality (0 = the scenario's image.jpeg_quality) and a
  // shrink-and-enlarge factor (1 = none).
  int jpeg_quality = 0;
  float rescale = 1.0f;
  // How long the shutter stays open (seconds; 0 = an instant): people moving in their clips
  // leave streaks (motion blur) centred on the labelled instant.
  float shutter = 0.0f;
  // Drawn values a randomizer records in the image's COCO entry (realism splits by them).
  nlohmann::ordered_json image_attributes = nlohmann::ordered_json::object();
};

}  // namespace wheelpose::generate
