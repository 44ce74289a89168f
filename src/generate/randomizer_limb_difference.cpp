// LimbDifference: some people have a leg or an arm removed below or above the knee/elbow.

#include "generate/randomizer.h"

namespace wheelpose::generate {
namespace {

class LimbDifference final : public Randomizer {
 public:
  explicit LimbDifference(const ConfigNode* c)
      : probability_(number_or(c, "probability", 1.0 / 16, 0.0, 1.0)),
        above_(number_or(c, "above_probability", 0.5, 0.0, 1.0)) {}

  void apply(FrameDraft& f, RandomStream&, const RandomizerContext&) const override {
    for (PersonDraft& p : f.people) {
      // Drawn per pool member (not per frame), so a person keeps their body across frames.
      RandomStream member(p.spec.seed, {"limb_difference"});
      p.spec.limbs = {};
      if (!member.bernoulli(probability_)) continue;
      const auto limb = static_cast<std::size_t>(member.uniform_int(0, 3));
      p.spec.limbs[limb] = member.bernoulli(above_) ? body::Cut::kAbove : body::Cut::kBelow;
    }
  }

  nlohmann::ordered_json parameters() const override {
    return {{"probability", probability_}, {"above_probability", above_}};
  }

 private:
  double probability_, above_;
};

}  // namespace

extern const RandomizerEntry kLimbDifferenceRandomizer = {
    "LimbDifference",
    "With `probability` = 1/16 per person, removes one limb (left/right leg or arm, uniform) "
    "above (`above_probability` = 0.5) or below the knee/elbow; the cut is capped and keypoints "
    "beyond it are labelled 0,0,0. Fixed per pool member. New in WheelPose (participants asked "
    "for amputees).",
    true, [](const ConfigNode* c) -> std::unique_ptr<Randomizer> {
      return std::make_unique<LimbDifference>(c);
    }};

}  // namespace wheelpose::generate
