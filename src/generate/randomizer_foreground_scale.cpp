// ForegroundScale: size of the people placed by ForegroundObjectPlacement.

#include "generate/randomizer.h"

namespace wheelpose::generate {
namespace {

class ForegroundScale final : public Randomizer {
 public:
  explicit ForegroundScale(const ConfigNode* c)
      : scale_(sampler_or(c, "scale", ScalarSampler::uniform(0.5, 3), 0.01, 100)) {}

  void apply(FrameDraft& f, RandomStream& rng, const RandomizerContext&) const override {
    if (f.environment == EnvironmentKind::kRoom) return;
    for (PersonDraft& p : f.people) p.scale = static_cast<float>(scale_.sample(rng));
  }

  nlohmann::ordered_json parameters() const override { return {{"scale", scale_.describe()}}; }

 private:
  ScalarSampler scale_;
};

}  // namespace

extern const RandomizerEntry kForegroundScaleRandomizer = {
    "ForegroundScale",
    "Scales every person uniformly by `scale` U(0.5, 3) (paper; the table's per-axis form "
    "would distort bodies). Off by default, like ForegroundObjectPlacement.",
    false, [](const ConfigNode* c) -> std::unique_ptr<Randomizer> {
      return std::make_unique<ForegroundScale>(c);
    }};

}  // namespace wheelpose::generate
