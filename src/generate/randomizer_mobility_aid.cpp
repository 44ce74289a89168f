// MobilityAid: some people hold a cane or forearm crutches, or have a walker in front of them.

#include "generate/randomizer.h"

namespace wheelpose::generate {
namespace {

class MobilityAidRandomizer final : public Randomizer {
 public:
  explicit MobilityAidRandomizer(const ConfigNode* c)
      : probability_(number_or(c, "probability", 0.1, 0.0, 1.0)),
        cane_(number_or(c, "cane_weight", 0.4, 0, 1e6)),
        crutches_(number_or(c, "crutches_weight", 0.4, 0, 1e6)),
        walker_(number_or(c, "walker_weight", 0.2, 0, 1e6)) {
    if (cane_ + crutches_ + walker_ <= 0) c->fail("the three weights add up to 0");
    type_ = ScalarSampler::categorical({static_cast<double>(body::MobilityAidType::kCane),
                                        static_cast<double>(body::MobilityAidType::kCrutches),
                                        static_cast<double>(body::MobilityAidType::kWalker)},
                                       {cane_, crutches_, walker_});
  }

  void apply(FrameDraft& f, RandomStream&, const RandomizerContext&) const override {
    for (PersonDraft& p : f.people) {
      // Per pool member, like the wheelchair: a person keeps their aid across frames.
      RandomStream member(p.spec.seed, {"mobility_aid_type"});
      p.spec.mobility_aid = body::MobilityAidType::kNone;
      if (!member.bernoulli(probability_)) continue;
      p.spec.mobility_aid = static_cast<body::MobilityAidType>(type_.sample(member));
    }
  }

  nlohmann::ordered_json parameters() const override {
    return {{"probability", probability_},
            {"cane_weight", cane_},
            {"crutches_weight", crutches_},
            {"walker_weight", walker_}};
  }

 private:
  double probability_, cane_, crutches_, walker_;
  ScalarSampler type_;  // over the aid types, by the weights
};

}  // namespace

extern const RandomizerEntry kMobilityAidRandomizer = {
    "MobilityAid",
    "With `probability` = 0.1 per person (fixed per pool member), a mobility aid: a cane in one "
    "hand (`cane_weight` 0.4), a forearm crutch in each hand (`crutches_weight` 0.4) or a "
    "walker standing in front of the knees (`walker_weight` 0.2). Aids are built at the posed "
    "hands, so they follow the clip; they are labelled as their own class (semantic id 5) and "
    "occlude like any object. New in WheelPose (not in the paper).",
    true, [](const ConfigNode* c) -> std::unique_ptr<Randomizer> {
      return std::make_unique<MobilityAidRandomizer>(c);
    }};

}  // namespace wheelpose::generate
