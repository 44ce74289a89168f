// HueOffset: hue rotation of the background objects' and the wall's textures.

#include "generate/randomizer.h"

namespace wheelpose::generate {
namespace {

class HueOffsetRandomizer final : public Randomizer {
 public:
  explicit HueOffsetRandomizer(const ConfigNode* c)
      : hue_(sampler_or(c, "hue_offset", ScalarSampler::uniform(-180, 180), -180, 180)) {}

  void apply(FrameDraft& f, RandomStream& rng, const RandomizerContext&) const override {
    for (ObjectDraft& o : f.objects)
      o.material.hue_offset_deg = static_cast<float>(hue_.sample(rng));
    f.wall.hue_offset_deg = static_cast<float>(hue_.sample(rng));
  }

  nlohmann::ordered_json parameters() const override { return {{"hue_offset", hue_.describe()}}; }

 private:
  ScalarSampler hue_;
};

}  // namespace

extern const RandomizerEntry kHueOffsetRandomizer = {
    "HueOffset",
    "Rotates the hue of each background object's and the wall's texture by `hue_offset` = "
    "U(−180, 180) degrees (paper).",
    true, [](const ConfigNode* c) -> std::unique_ptr<Randomizer> {
      return std::make_unique<HueOffsetRandomizer>(c);
    }};

}  // namespace wheelpose::generate
