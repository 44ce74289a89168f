// HangingClothes: coats, jackets and shirts on hangers against a room's side wall — shapes in
// everyday fabrics, as high as a person, with no person in them: hard negatives.

#include <cmath>

#include "generate/garment_palette.h"
#include "generate/randomizer.h"

namespace wheelpose::generate {
namespace {

class HangingClothes final : public Randomizer {
 public:
  explicit HangingClothes(const ConfigNode* c)
      : min_(integer_or(c, "min_count", 0, 0, 100)), max_(integer_or(c, "max_count", 1, 0, 100)) {
    if (max_ < min_) c->fail("max_count is below min_count");
  }

  void apply(FrameDraft& f, RandomStream& rng, const RandomizerContext& ctx) const override {
    const std::int64_t n = rng.uniform_int(min_, max_);
    for (std::int64_t i = 0; i < n; ++i) {
      // Every value is drawn whatever the frame is, so rooms and walls keep their streams.
      const auto pick = rng.uniform_int(
          0, std::max<std::int64_t>(0, static_cast<std::int64_t>(ctx.hanging_clothes.size()) - 1));
      const float side = rng.bernoulli(0.5) ? 1.0f : -1.0f;
      const double along = rng.uniform(-0.35, 0.35);
      const double quarter_turns = static_cast<double>(rng.uniform_int(0, 3));
      const double jitter = rng.uniform(-0.2, 0.2);
      const scene::Material fabric =
          garment_material(rng, "hanging_clothes", GarmentColours::kPalette);
      if (f.environment != EnvironmentKind::kRoom || f.room.outdoor ||
          ctx.hanging_clothes.empty()) {
        continue;
      }
      ObjectDraft clothes;
      clothes.furniture = ctx.hanging_clothes[static_cast<std::size_t>(pick)];
      clothes.position = Eigen::Vector3f(side * (0.5f * f.room.size.x() - 0.35f), 0,
                                         static_cast<float>(along) * f.room.size.y());
      clothes.rotation = Eigen::AngleAxisf(static_cast<float>(quarter_turns * M_PI / 2 + jitter),
                                           Eigen::Vector3f::UnitY());
      clothes.material = fabric;
      f.objects.push_back(clothes);
    }
  }

  nlohmann::ordered_json parameters() const override {
    return {{"min_count", min_}, {"max_count", max_}};
  }

 private:
  long long min_, max_;
};

}  // namespace

extern const RandomizerEntry kHangingClothesRandomizer = {
    "HangingClothes",
    "Rooms only: adds `min_count`…`max_count` = 0…1 racks of coats, jackets and shirts on "
    "hangers (the two \"Hanging clothes\" models of sweethome3d-furniture's KatorLegaz catalogue, "
    "CC-BY 3.0 US, at their catalogued size and height above the floor) against a side wall, "
    "turned a random quarter turn ± 11°, in one garment fabric of the palette. Labelled as "
    "objects: clothes with no person in them, which a model must learn are not people. None "
    "when the catalogue is not installed. New in WheelPose.",
    false, [](const ConfigNode* c) -> std::unique_ptr<Randomizer> {
      return std::make_unique<HangingClothes>(c);
    }};

}  // namespace wheelpose::generate
