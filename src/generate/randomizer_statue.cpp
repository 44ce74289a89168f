// Statue: human shapes that are not people (statues and mannequins), as hard negatives.

#include "generate/randomizer.h"

namespace wheelpose::generate {
namespace {

// One material for the whole body: weathered stone, bronze, or a plaster or plastic mannequin.
scene::Material statue_material(RandomStream& rng) {
  scene::Material m;
  m.name = "statue";
  const double u = rng.uniform01();
  const auto shade = [&rng](float lo, float hi) { return static_cast<float>(rng.uniform(lo, hi)); };
  if (u < 0.4) {  // stone: a pale grey or sandstone marble
    const Eigen::Vector3f stone = rng.bernoulli(0.5) ? Eigen::Vector3f(0.62f, 0.61f, 0.58f)
                                                     : Eigen::Vector3f(0.66f, 0.56f, 0.42f);
    m.diffuse = Eigen::Vector3f::Ones();
    m.texture.kind = scene::TextureKind::kMarble;
    m.texture.color_a = stone * shade(0.8f, 1.15f);
    m.texture.color_b = stone * shade(0.55f, 0.8f);
    m.texture.scale = shade(1, 4);
    m.texture.turbulence = shade(0.5f, 1.5f);
    m.texture.seed = rng.next_u64();
    m.specular = shade(0.02f, 0.1f);
    m.shininess = 16;
  } else if (u < 0.7) {  // bronze: dark, greenish or brown, with a metallic highlight
    m.diffuse = rng.bernoulli(0.5) ? Eigen::Vector3f(0.16f, 0.11f, 0.06f)
                                   : Eigen::Vector3f(0.10f, 0.14f, 0.11f);
    m.diffuse *= shade(0.8f, 1.3f);
    m.specular = shade(0.3f, 0.6f);
    m.shininess = shade(30, 80);
  } else {  // mannequin: white, grey, beige or black plastic
    const Eigen::Vector3f plastic[] = {
        {0.8f, 0.8f, 0.78f}, {0.45f, 0.45f, 0.45f}, {0.7f, 0.58f, 0.46f}, {0.05f, 0.05f, 0.05f}};
    m.diffuse = plastic[rng.uniform_int(0, 3)] * shade(0.9f, 1.1f);
    m.specular = shade(0.15f, 0.4f);
    m.shininess = shade(20, 60);
  }
  return m;
}

class Statue final : public Randomizer {
 public:
  explicit Statue(const ConfigNode* c) : count_(c, 1) {}

  void apply(FrameDraft& f, RandomStream& rng, const RandomizerContext& ctx) const override {
    const std::int64_t n = rng.uniform_int(count_.min, count_.max);
    for (std::int64_t i = 0; i < n; ++i) {
      StatueDraft statue;
      statue.spec = body::sample_spec(rng.next_u64());
      statue.spec.wheelchair = body::WheelchairType::kNone;  // standing on its feet or plinth
      statue.material = statue_material(rng);
      if (!ctx.clip_durations.empty()) {
        statue.clip = static_cast<int>(
            rng.uniform_int(0, static_cast<std::int64_t>(ctx.clip_durations.size()) - 1));
        statue.time = rng.uniform01() * ctx.clip_durations[static_cast<std::size_t>(statue.clip)];
      }
      const float heading = static_cast<float>(rng.uniform(0, 2 * M_PI));
      statue.rotation = Eigen::AngleAxisf(heading, Eigen::Vector3f::UnitY());
      if (f.environment == EnvironmentKind::kRoom) {
        // Along a side wall, where furniture stands, out of the people's middle of the room.
        const float side = rng.bernoulli(0.5) ? 1.0f : -1.0f;
        statue.position =
            Eigen::Vector3f(side * static_cast<float>(rng.uniform(0.32, 0.42)) * f.room.size.x(), 0,
                            static_cast<float>(rng.uniform(-0.35, 0.35)) * f.room.size.y());
      } else {
        statue.position = people_volume_point(rng);
        statue.scale = static_cast<float>(count_.size.sample(rng));
      }
      f.statues.push_back(statue);
    }
  }

  nlohmann::ordered_json parameters() const override { return count_.parameters(); }

 private:
  DistractorCount count_;
};

}  // namespace

extern const RandomizerEntry kStatueRandomizer = {
    "Statue",
    "Adds `min_count`…`max_count` = 0…1 statues or mannequins: a random MakeHuman body, bare "
    "and bald, standing in the pose of a random clip, all of one material — stone (0.4: pale "
    "grey or sandstone marble), bronze (0.3) or mannequin plastic (0.3: white, grey, beige or "
    "black). Rooms: along a side wall; wall layout: in the people's volume, scaled by `size` "
    "U(0.5, 3). Labelled as objects, never as people: human shapes a model must learn are not "
    "people. New in WheelPose.",
    false,
    [](const ConfigNode* c) -> std::unique_ptr<Randomizer> { return std::make_unique<Statue>(c); }};

}  // namespace wheelpose::generate
