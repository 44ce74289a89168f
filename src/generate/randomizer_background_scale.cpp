// BackgroundOccluderScale: per-axis scale of the background objects.

#include "generate/randomizer.h"

namespace wheelpose::generate {
namespace {

class BackgroundOccluderScale final : public Randomizer {
 public:
  explicit BackgroundOccluderScale(const ConfigNode* c)
      : scale_(sampler_or(c, "scale", ScalarSampler::uniform(1, 12), 0.01, 1000)),
        room_scale_(sampler_or(c, "room_scale", ScalarSampler::uniform(0.4, 1.6), 0.01, 100)) {}

  void apply(FrameDraft& f, RandomStream& rng, const RandomizerContext&) const override {
    const ScalarSampler& s = f.environment == EnvironmentKind::kRoom ? room_scale_ : scale_;
    for (ObjectDraft& o : f.objects) {
      const float x = static_cast<float>(s.sample(rng));
      const float y = static_cast<float>(s.sample(rng));
      const float z = static_cast<float>(s.sample(rng));
      o.scale = Eigen::Vector3f(x, y, z);
    }
  }

  nlohmann::ordered_json parameters() const override {
    return {{"scale", scale_.describe()}, {"room_scale", room_scale_.describe()}};
  }

 private:
  ScalarSampler scale_, room_scale_;
};

}  // namespace

extern const RandomizerEntry kBackgroundOccluderScaleRandomizer = {
    "BackgroundOccluderScale",
    "Scales each background object independently per axis by `scale` = U(1, 12) (paper), or "
    "`room_scale` = U(0.4, 1.6) for furniture in rooms.",
    true, [](const ConfigNode* c) -> std::unique_ptr<Randomizer> {
      return std::make_unique<BackgroundOccluderScale>(c);
    }};

}  // namespace wheelpose::generate
