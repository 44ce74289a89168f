// Wheelchair: type and colours of each person's chair.

#include "generate/randomizer.h"
#include "generate/wheelchair_palette.h"

namespace wheelpose::generate {
namespace {

class WheelchairRandomizer final : public Randomizer {
 public:
  explicit WheelchairRandomizer(const ConfigNode* c)
      : manual_(number_or(c, "manual_weight", 0.6, 0, 1e6)),
        sport_(number_or(c, "sport_weight", 0.15, 0, 1e6)),
        power_(number_or(c, "power_weight", 0.25, 0, 1e6)),
        cc_by_(number_or(c, "cc_by_weight", 0.0, 0, 1e6)),
        none_(number_or(c, "none_weight", 0.0, 0, 1e6)),
        headrest_(number_or(c, "power_headrest_probability", 1.0, 0, 1)),
        colour_style_(chair_colours_of(c)) {
    if (manual_ + sport_ + power_ + cc_by_ + none_ <= 0) c->fail("the weights add up to 0");
    type_ = ScalarSampler::categorical({static_cast<double>(body::WheelchairType::kManual),
                                        static_cast<double>(body::WheelchairType::kSport),
                                        static_cast<double>(body::WheelchairType::kPower),
                                        static_cast<double>(body::WheelchairType::kCcBy),
                                        static_cast<double>(body::WheelchairType::kNone)},
                                       {manual_, sport_, power_, cc_by_, none_});
  }

  void apply(FrameDraft& f, RandomStream&, const RandomizerContext&) const override {
    for (PersonDraft& p : f.people) {
      RandomStream member(p.spec.seed, {"wheelchair_type"});
      p.spec.wheelchair = static_cast<body::WheelchairType>(type_.sample(member));
      p.chair_colours = wheelchair_colours(member, colour_style_);
      // Drawn only when asked for, so the default's frames keep their bytes.
      if (headrest_ < 1) p.spec.chair_headrest = member.uniform(0.0, 1.0) < headrest_;
    }
  }

  nlohmann::ordered_json parameters() const override {
    nlohmann::ordered_json j = {
        {"manual_weight", manual_}, {"sport_weight", sport_},
        {"power_weight", power_},   {"cc_by_weight", cc_by_},
        {"none_weight", none_},     {"colours", chair_colours_name(colour_style_)}};
    // Written only when set, so the scenarios of earlier runs read back unchanged.
    if (headrest_ < 1) j["power_headrest_probability"] = headrest_;
    return j;
  }

 private:
  double manual_, sport_, power_, cc_by_, none_;
  double headrest_;  // the share of power chairs with a tall back and a headrest
  ChairColours colour_style_;
  ScalarSampler type_;  // over the WheelchairType values, by the weights
};

}  // namespace

extern const RandomizerEntry kWheelchairRandomizer = {
    "Wheelchair",
    "Chooses each person's wheelchair type with weights `manual_weight` 0.6, `sport_weight` "
    "0.15, `power_weight` 0.25 and `cc_by_weight` 0 (the CC-BY \"Wheel Chair\" model by bgamage "
    "from `sweethome3d-furniture`, scaled under the fitted seat; opt-in because anything "
    "published with it must carry its credit) and `none_weight` 0 (no wheelchair: the person "
    "stands on the floor, playing the clip's upper body on straight legs; for test sets of "
    "people without wheelchairs), and its colours: `colours` = palette (frames black, silver, "
    "graphite or white, a third anodised in a colour; upholstery black, charcoal or navy, rarely "
    "a dark colour; chrome, aluminium or black trim; dark grey tyres) or uniform (the earlier "
    "draw: frame U(0.05, 0.9), upholstery U(0.02, 0.4), trim U(0.3, 0.8) per channel). "
    "`power_headrest_probability` 1: the share of power chairs that are rehab chairs, a back "
    "0.50-0.60 m tall and a headrest behind the head; the others are folding power chairs with "
    "a 0.40-0.50 m back and no headrest (below 1 each person's draw is recorded as "
    "`power_chair_headrest` on power-chair users). "
    "Dimensions are fitted to the body by the body stage. Fixed per pool member. New in WheelPose "
    "(the authors' chair was a cube placeholder).",
    true, [](const ConfigNode* c) -> std::unique_ptr<Randomizer> {
      return std::make_unique<WheelchairRandomizer>(c);
    }};

}  // namespace wheelpose::generate
