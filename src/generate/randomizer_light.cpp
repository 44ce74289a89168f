// Light: colour, intensity and on/off state of the seven point lights.

#include "generate/randomizer.h"
#include "scene/blackbody.h"

namespace wheelpose::generate {
namespace {

// The authors' light rig (world positions); the seventh is moved by LightPositionRotation.
const Eigen::Vector3f kWallLights[7] = {{-10, 0, 0}, {10, 0, 0}, {0, 10, 0}, {0, -11, 0},
                                        {0, 0, 10},  {0, 0, -7}, {0, 7, 2}};

class LightRandomizer final : public Randomizer {
 public:
  explicit LightRandomizer(const ConfigNode* c)
      : colour_(sampler_or(c, "color", ScalarSampler::uniform(0, 1), 0, 1)),
        lumens_(sampler_or(c, "intensity_lumen", ScalarSampler::uniform(5000, 50000), 0, 1e7)),
        on_(number_or(c, "on_probability", 0.8, 0, 1)),
        lumens_per_unit_(number_or(c, "lumen_per_unit", 1000, 1, 1e9)),
        blackbody_(c != nullptr && c->has("color_temperature")),
        kelvin_(sampler_or(c, "color_temperature", ScalarSampler::constant(6500),
                           scene::kMinColourTemperature, scene::kMaxColourTemperature)),
        tint_(number_or(c, "tint_probability", 0, 0, 1)) {}

  void apply(FrameDraft& f, RandomStream& rng, const RandomizerContext&) const override {
    f.lights.clear();
    for (int i = 0; i < 7; ++i) {
      scene::PointLight l;
      if (f.environment == EnvironmentKind::kRoom) {
        // Ceiling lights spread over the room.
        const float u = (static_cast<float>(i % 4) + 0.5f) / 4 - 0.5f;
        const float v = i < 4 ? -0.25f : 0.25f;
        l.position =
            Eigen::Vector3f(u * f.room.size.x(), f.room.height - 0.15f, v * f.room.size.y());
      } else {
        l.position = kWallLights[i];
      }
      // The paper's lights draw each channel; black-body lights are bulbs and daylight, with
      // a rare coloured one (a party bulb, a screen) when tint_probability > 0.
      if (blackbody_ && !(tint_ > 0 && rng.bernoulli(tint_))) {
        l.color = scene::blackbody_rgb(kelvin_.sample(rng));
      } else {
        l.color = Eigen::Vector3f(static_cast<float>(colour_.sample(rng)),
                                  static_cast<float>(colour_.sample(rng)),
                                  static_cast<float>(colour_.sample(rng)));
      }
      l.intensity = static_cast<float>(lumens_.sample(rng) / lumens_per_unit_);
      if (f.environment == EnvironmentKind::kRoom) l.intensity *= 0.1f;  // metres away, not 10 m
      l.on = rng.bernoulli(on_);
      l.radius = 0.1f;
      f.lights.push_back(l);
    }
  }

  nlohmann::ordered_json parameters() const override {
    nlohmann::ordered_json p = {{"color", colour_.describe()},
                                {"intensity_lumen", lumens_.describe()},
                                {"on_probability", on_},
                                {"lumen_per_unit", lumens_per_unit_}};
    if (blackbody_) {
      p["color_temperature"] = kelvin_.describe();
      p["tint_probability"] = tint_;
    }
    return p;
  }

 private:
  ScalarSampler colour_, lumens_;
  double on_, lumens_per_unit_;
  bool blackbody_;
  ScalarSampler kelvin_;
  double tint_;
};

}  // namespace

extern const RandomizerEntry kLightRandomizer = {
    "Light",
    "Seven point lights at the authors' positions (±10 m on x, 10 m up, 11 m down, 10 m in "
    "front, 7 m behind, and the moving one; on the ceiling in rooms), each with colour `color` "
    "U(0, 1) per channel (the authors' scene value; their code default was U(0.4, 1)), "
    "`intensity_lumen` U(5000, 50000) (paper), switched on with `on_probability` 0.8 (scene "
    "value; code default 0.5). Lumens become our intensity (irradiance at 1 m, sun = 1) by "
    "dividing by `lumen_per_unit` = 1000, so a light 10 m away adds 5–50 % of the sun; ceiling "
    "lights in rooms are a tenth of that. With `color_temperature` (kelvin, 1667–25000; e.g. "
    "U(2700, 6500) from warm bulbs to daylight) each light is instead a black body of that "
    "temperature (the Planckian locus, Kim et al. 2002), and with `tint_probability` (default 0) "
    "a light keeps the per-channel `color` (a coloured bulb). New in WheelPose.",
    true, [](const ConfigNode* c) -> std::unique_ptr<Randomizer> {
      return std::make_unique<LightRandomizer>(c);
    }};

}  // namespace wheelpose::generate
