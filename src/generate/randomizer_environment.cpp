// Environment: the paper's layout (people floating in front of a textured wall) or a room.

#include "generate/randomizer.h"

namespace wheelpose::generate {
namespace {

class EnvironmentRandomizer final : public Randomizer {
 public:
  explicit EnvironmentRandomizer(const ConfigNode* c)
      : room_probability_(number_or(c, "room_probability", 0.0, 0.0, 1.0)),
        room_width_(sampler_or(c, "room_width", ScalarSampler::uniform(6, 12), 3, 50)),
        room_depth_(sampler_or(c, "room_depth", ScalarSampler::uniform(6, 12), 3, 50)),
        room_height_(sampler_or(c, "room_height", ScalarSampler::uniform(2.5, 3.2), 2, 10)),
        sky_(sampler_or(c, "sky_radiance", ScalarSampler::uniform(0.1, 0.4), 0, 10)) {}

  void apply(FrameDraft& f, RandomStream& rng, const RandomizerContext&) const override {
    f.environment = rng.bernoulli(room_probability_) ? EnvironmentKind::kRoom : EnvironmentKind::kWall;
    f.room.size = Eigen::Vector2f(static_cast<float>(room_width_.sample(rng)),
                                  static_cast<float>(room_depth_.sample(rng)));
    f.room.height = static_cast<float>(room_height_.sample(rng));
    f.room.floor = random_material(rng, "floor");
    f.room.walls = random_material(rng, "walls");
    f.wall = random_material(rng, "wall");
    scene::Environment sky;
    const float radiance = static_cast<float>(sky_.sample(rng));
    sky.color = Eigen::Vector3f(0.85f, 0.92f, 1.0f) * radiance;
    f.sky = sky;
  }

  nlohmann::ordered_json parameters() const override {
    return {{"room_probability", room_probability_},
            {"room_width", room_width_.describe()},
            {"room_depth", room_depth_.describe()},
            {"room_height", room_height_.describe()},
            {"sky_radiance", sky_.describe()}};
  }

 private:
  double room_probability_;
  ScalarSampler room_width_, room_depth_, room_height_, sky_;
};

}  // namespace

extern const RandomizerEntry kEnvironmentRandomizer = {
    "Environment",
    "Chooses the layout: `wall` (the paper's: people and occluders float in front of a 30 m "
    "textured wall at z = −10, no floor) with probability 1 − `room_probability` (default 0), "
    "else `room` (floor and four walls of `room_width` × `room_depth` U(6, 12) m, "
    "`room_height` U(2.5, 3.2) m, wheelchairs standing on the floor, camera at standing or "
    "seated eye height). Also sets the uniform sky light (`sky_radiance` U(0.1, 0.4), relative "
    "to the sun's 1) that stands in for the authors' physically based sky. New in WheelPose.",
    true, [](const ConfigNode* c) -> std::unique_ptr<Randomizer> {
      return std::make_unique<EnvironmentRandomizer>(c);
    }};

}  // namespace wheelpose::generate
