// EmptyWheelchair: distractor wheelchairs with nobody in them.

#include "generate/randomizer.h"

namespace wheelpose::generate {
namespace {

class EmptyWheelchair final : public Randomizer {
 public:
  explicit EmptyWheelchair(const ConfigNode* c)
      : min_(integer_or(c, "min_count", 0, 0, 1000)),
        max_(integer_or(c, "max_count", 2, 0, 1000)),
        size_(sampler_or(c, "size", ScalarSampler::uniform(0.5, 3), 0.01, 100)) {
    if (max_ < min_) c->fail("max_count is below min_count");
  }

  void apply(FrameDraft& f, RandomStream& rng, const RandomizerContext&) const override {
    const std::int64_t n = rng.uniform_int(min_, max_);
    for (std::int64_t i = 0; i < n; ++i) {
      EmptyChairDraft chair;
      const double u = rng.uniform01();
      chair.type = u < 0.6    ? body::WheelchairType::kManual
                   : u < 0.75 ? body::WheelchairType::kSport
                              : body::WheelchairType::kPower;
      chair.seed = rng.next_u64();
      const float heading = static_cast<float>(rng.uniform(0, 2 * M_PI));
      if (f.environment == EnvironmentKind::kRoom) {
        chair.position =
            Eigen::Vector3f(static_cast<float>(rng.uniform(-0.35, 0.35)) * f.room.size.x(), 0,
                            static_cast<float>(rng.uniform(-0.35, 0.35)) * f.room.size.y());
        chair.rotation = Eigen::AngleAxisf(heading, Eigen::Vector3f::UnitY());
      } else {
        chair.position = Eigen::Vector3f(static_cast<float>(rng.uniform(-7.5, 7.5)),
                                         static_cast<float>(rng.uniform(-7.5, 7.5)),
                                         static_cast<float>(rng.uniform(-4, 1)));
        chair.rotation = Eigen::AngleAxisf(heading, Eigen::Vector3f::UnitY());
        chair.scale = static_cast<float>(size_.sample(rng));
      }
      f.empty_chairs.push_back(chair);
    }
  }

  nlohmann::ordered_json parameters() const override {
    return {{"min_count", min_}, {"max_count", max_}, {"size", size_.describe()}};
  }

 private:
  long long min_, max_;
  ScalarSampler size_;
};

}  // namespace

extern const RandomizerEntry kEmptyWheelchairRandomizer = {
    "EmptyWheelchair",
    "Adds `min_count`…`max_count` = 0…2 wheelchairs with nobody in them (type manual 0.6, sport "
    "0.15, power 0.25), so a model learns that a chair is not a person. Wall layout: placed in "
    "the people's volume, scaled by `size` U(0.5, 3); rooms: standing on the floor. They get no "
    "annotation. New in WheelPose.",
    true, [](const ConfigNode* c) -> std::unique_ptr<Randomizer> {
      return std::make_unique<EmptyWheelchair>(c);
    }};

}  // namespace wheelpose::generate
