// SunAngle: the sun's direction from a solar position.

#include "generate/randomizer.h"

namespace wheelpose::generate {
namespace {

class SunAngle final : public Randomizer {
 public:
  explicit SunAngle(const ConfigNode* c)
      : hour_(sampler_or(c, "hour", ScalarSampler::uniform(0, 24), 0, 24)),
        day_(sampler_or(c, "day_of_year", ScalarSampler::uniform(0, 365), 0, 366)),
        latitude_(sampler_or(c, "latitude", ScalarSampler::uniform(-90, 90), -90, 90)),
        intensity_(sampler_or(c, "intensity", ScalarSampler::constant(1.0), 0, 100)) {}

  void apply(FrameDraft& f, RandomStream& rng, const RandomizerContext&) const override {
    scene::SolarPosition s;
    s.hour = static_cast<float>(hour_.sample(rng));
    s.day_of_year = static_cast<float>(day_.sample(rng));
    s.latitude_deg = static_cast<float>(latitude_.sample(rng));
    f.sun.solar = s;
    f.sun.enabled = true;
    f.sun.intensity = static_cast<float>(intensity_.sample(rng));
  }

  nlohmann::ordered_json parameters() const override {
    return {{"hour", hour_.describe()},
            {"day_of_year", day_.describe()},
            {"latitude", latitude_.describe()},
            {"intensity", intensity_.describe()}};
  }

 private:
  ScalarSampler hour_, day_, latitude_, intensity_;
};

}  // namespace

extern const RandomizerEntry kSunAngleRandomizer = {
    "SunAngle",
    "Points the sun from a solar position: `hour` U(0, 24), `day_of_year` U(0, 365), `latitude` "
    "U(−90, 90) (paper); below the horizon it does not light the scene. `intensity` 1 is our "
    "unit of irradiance (a white surface facing the sun is 1.0 before exposure), standing for "
    "the authors' 10,000 lux sun.",
    true, [](const ConfigNode* c) -> std::unique_ptr<Randomizer> {
      return std::make_unique<SunAngle>(c);
    }};

}  // namespace wheelpose::generate
