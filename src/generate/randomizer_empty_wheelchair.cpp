// EmptyWheelchair: distractor wheelchairs with nobody in them.

#include "generate/randomizer.h"
#include "generate/wheelchair_palette.h"

namespace wheelpose::generate {
namespace {

class EmptyWheelchair final : public Randomizer {
 public:
  explicit EmptyWheelchair(const ConfigNode* c)
      : count_(c, 2), colour_style_(chair_colours_of(c)) {}

  void apply(FrameDraft& f, RandomStream& rng, const RandomizerContext&) const override {
    const std::int64_t n = rng.uniform_int(count_.min, count_.max);
    for (std::int64_t i = 0; i < n; ++i) {
      EmptyChairDraft chair;
      const double u = rng.uniform01();
      chair.type = u < 0.6    ? body::WheelchairType::kManual
                   : u < 0.75 ? body::WheelchairType::kSport
                              : body::WheelchairType::kPower;
      chair.seed = rng.next_u64();
      // The palette's draw comes from the chair's own stream, so the frame's draws stay as they
      // were; uniform keeps the colours body::make_empty_wheelchair draws itself.
      if (colour_style_ == ChairColours::kPalette) {
        RandomStream own(chair.seed, {"empty_wheelchair_colours"});
        chair.colours = wheelchair_colours(own, ChairColours::kPalette);
      }
      const float heading = static_cast<float>(rng.uniform(0, 2 * M_PI));
      if (f.environment == EnvironmentKind::kRoom) {
        chair.position =
            Eigen::Vector3f(static_cast<float>(rng.uniform(-0.35, 0.35)) * f.room.size.x(), 0,
                            static_cast<float>(rng.uniform(-0.35, 0.35)) * f.room.size.y());
        chair.rotation = Eigen::AngleAxisf(heading, Eigen::Vector3f::UnitY());
      } else {
        chair.position = people_volume_point(rng);
        chair.rotation = Eigen::AngleAxisf(heading, Eigen::Vector3f::UnitY());
        chair.scale = static_cast<float>(count_.size.sample(rng));
      }
      f.empty_chairs.push_back(chair);
    }
  }

  nlohmann::ordered_json parameters() const override {
    nlohmann::ordered_json p = count_.parameters();
    p["colours"] = chair_colours_name(colour_style_);
    return p;
  }

 private:
  DistractorCount count_;
  ChairColours colour_style_;
};

}  // namespace

extern const RandomizerEntry kEmptyWheelchairRandomizer = {
    "EmptyWheelchair",
    "Adds `min_count`…`max_count` = 0…2 wheelchairs with nobody in them (type manual 0.6, sport "
    "0.15, power 0.25), so a model learns that a chair is not a person. Wall layout: placed in "
    "the people's volume, scaled by `size` U(0.5, 3); rooms: standing on the floor. They get no "
    "annotation. `colours` = palette as the Wheelchair randomizer's, or uniform (the chair's own "
    "earlier draw: frame U(0.05, 0.9), upholstery U(0.02, 0.25), trim U(0.5, 0.85) per channel). "
    "New in WheelPose.",
    true, [](const ConfigNode* c) -> std::unique_ptr<Randomizer> {
      return std::make_unique<EmptyWheelchair>(c);
    }};

}  // namespace wheelpose::generate
