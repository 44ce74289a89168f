// LightPositionRotation: moves the seventh point light around its initial position.

#include "generate/randomizer.h"

namespace wheelpose::generate {
namespace {

class LightPositionRotation final : public Randomizer {
 public:
  explicit LightPositionRotation(const ConfigNode* c)
      : offset_(sampler_or(c, "offset", ScalarSampler::uniform(-3.65, 3.65))) {}

  void apply(FrameDraft& f, RandomStream& rng, const RandomizerContext&) const override {
    if (f.lights.size() < 7 || f.environment == EnvironmentKind::kRoom) return;
    const Eigen::Vector3f offset(static_cast<float>(offset_.sample(rng)),
                                 static_cast<float>(offset_.sample(rng)),
                                 static_cast<float>(offset_.sample(rng)));
    f.lights[6].position = Eigen::Vector3f(0, 7, 2) + offset;
  }

  nlohmann::ordered_json parameters() const override { return {{"offset", offset_.describe()}}; }

 private:
  ScalarSampler offset_;
};

}  // namespace

extern const RandomizerEntry kLightPositionRotationRandomizer = {
    "LightPositionRotation",
    "Moves the seventh light to (0, 7, 2) + (`offset`, `offset`, `offset`), `offset` "
    "U(−3.65, 3.65) m per axis (paper). The paper's rotation offset U(−50, 50)° has no effect on "
    "a point light and is not sampled. Wall layout only.",
    true, [](const ConfigNode* c) -> std::unique_ptr<Randomizer> {
      return std::make_unique<LightPositionRotation>(c);
    }};

}  // namespace wheelpose::generate
