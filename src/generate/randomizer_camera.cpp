// Camera: position, orientation and field of view.

#include "generate/randomizer.h"

namespace wheelpose::generate {
namespace {

// Camera → world rotation that looks from `eye` toward `target` with +Y up (camera looks −Z).
Eigen::Quaternionf look_at(const Eigen::Vector3f& eye, const Eigen::Vector3f& target) {
  const Eigen::Vector3f forward = (target - eye).normalized();
  Eigen::Vector3f right = forward.cross(Eigen::Vector3f::UnitY());
  if (right.squaredNorm() < 1e-8f) right = Eigen::Vector3f::UnitX();
  right.normalize();
  const Eigen::Vector3f up = right.cross(forward);
  Eigen::Matrix3f r;
  r.col(0) = right;
  r.col(1) = up;
  r.col(2) = -forward;
  return Eigen::Quaternionf(r);
}

class CameraRandomizer final : public Randomizer {
 public:
  explicit CameraRandomizer(const ConfigNode* c)
      : fov_(sampler_or(c, "field_of_view", ScalarSampler::uniform(5, 50), 1, 170)),
        focal_(sampler_or(c, "focal_length", ScalarSampler::uniform(1, 23), 0, 1000)),
        offset_(sampler_or(c, "position_offset", ScalarSampler::uniform(-5, 5))),
        rotation_(sampler_or(c, "rotation_offset", ScalarSampler::uniform(-5, 5))),
        room_fov_(sampler_or(c, "room_field_of_view", ScalarSampler::uniform(45, 75), 1, 170)),
        room_height_(sampler_or(c, "room_height", ScalarSampler::uniform(0.9, 1.8), 0.1, 10)) {
    if (c != nullptr) {
      const std::string walls = c->get_string("room_walls", "ends");
      if (walls != "ends" && walls != "all")
        c->child("room_walls").fail("expected ends or all, not '" + walls + "'");
      any_wall_ = walls == "all";
    }
  }

  void apply(FrameDraft& f, RandomStream& rng, const RandomizerContext& ctx) const override {
    scene::Camera& cam = f.camera;
    cam.width = ctx.width;
    cam.height = ctx.height;
    cam.focal_length_mm = 0;  // the FOV drives projection, as in the authors' camera
    f.nominal_focal_length_mm = static_cast<float>(focal_.sample(rng));
    const Eigen::Vector3d noise_deg(rotation_.sample(rng), rotation_.sample(rng),
                                    rotation_.sample(rng));
    const Eigen::Quaternionf noise = euler_xyz_extrinsic(noise_deg * (M_PI / 180.0)).cast<float>();
    if (f.environment == EnvironmentKind::kRoom) {
      Eigen::Vector3f centre = Eigen::Vector3f::Zero();
      for (const PersonDraft& p : f.people) centre += p.position;
      if (!f.people.empty()) centre /= static_cast<float>(f.people.size());
      centre.y() = 0.7f;
      // Which wall: an end wall (across the room's depth), or with `room_walls: all` a side
      // wall as often as an end wall.
      const bool side_wall = any_wall_ && rng.bernoulli(0.5);
      const float side = rng.bernoulli(0.5) ? 1.0f : -1.0f;
      // Height before position along the wall: the order GCC gave the arguments of the one
      // expression these draws once were, kept so earlier datasets regenerate byte for byte.
      const float height = static_cast<float>(room_height_.sample(rng));
      const float along = static_cast<float>(rng.uniform(-0.4, 0.4));
      const Eigen::Vector3f eye =
          side_wall
              ? Eigen::Vector3f(side * 0.45f * f.room.size.x(), height, along * f.room.size.y())
              : Eigen::Vector3f(along * f.room.size.x(), height, side * 0.45f * f.room.size.y());
      cam.position = eye;
      cam.orientation = (look_at(eye, centre) * noise).normalized();
      cam.vfov_deg = static_cast<float>(room_fov_.sample(rng));
      return;
    }
    cam.position = Eigen::Vector3f(static_cast<float>(offset_.sample(rng)),
                                   static_cast<float>(offset_.sample(rng)),
                                   15.0f + static_cast<float>(offset_.sample(rng)));
    cam.orientation = noise;
    cam.vfov_deg = static_cast<float>(fov_.sample(rng));
  }

  nlohmann::ordered_json parameters() const override {
    nlohmann::ordered_json j = {
        {"field_of_view", fov_.describe()},           {"focal_length", focal_.describe()},
        {"position_offset", offset_.describe()},      {"rotation_offset", rotation_.describe()},
        {"room_field_of_view", room_fov_.describe()}, {"room_height", room_height_.describe()}};
    // Written only when set, so the scenarios of earlier runs read back unchanged.
    if (any_wall_) j["room_walls"] = "all";
    return j;
  }

 private:
  ScalarSampler fov_, focal_, offset_, rotation_, room_fov_, room_height_;
  bool any_wall_ = false;
};

}  // namespace

extern const RandomizerEntry kCameraRandomizer = {
    "Camera",
    "Wall layout (paper): the camera at (0, 0, 15) + `position_offset` U(−5, 5) m per axis, "
    "looking down −Z turned by `rotation_offset` U(−5, 5) degrees per axis, vertical "
    "`field_of_view` U(5, 50) degrees. `focal_length` U(1, 23) mm is drawn and recorded as the "
    "authors did, but as in their (non-physical) Unity camera the field of view drives the "
    "projection. Rooms: the camera stands near one end wall at `room_height` U(0.9, 1.8) m "
    "(seated to standing eye height), looks at the people's centre 0.7 m above the floor with "
    "the same rotation noise, `room_field_of_view` U(45, 75) degrees; `room_walls: all` puts it "
    "by a side wall half of the time.",
    true, [](const ConfigNode* c) -> std::unique_ptr<Randomizer> {
      return std::make_unique<CameraRandomizer>(c);
    }};

}  // namespace wheelpose::generate
