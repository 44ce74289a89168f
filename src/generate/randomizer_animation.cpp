// NonTagAnimation: each person plays a random clip at a random time.

#include "generate/randomizer.h"

namespace wheelpose::generate {
namespace {

class NonTagAnimation final : public Randomizer {
 public:
  explicit NonTagAnimation(const ConfigNode*) {}

  void apply(FrameDraft& f, RandomStream& rng, const RandomizerContext& ctx) const override {
    if (ctx.clip_durations.empty()) return;
    const auto last = static_cast<std::int64_t>(ctx.clip_durations.size()) - 1;
    for (PersonDraft& p : f.people) {
      p.clip = static_cast<int>(rng.uniform_int(0, last));
      p.time = rng.uniform01() * ctx.clip_durations[static_cast<std::size_t>(p.clip)];
    }
  }

  nlohmann::ordered_json parameters() const override {
    return {{"clip", "uniform over the motion clips"}, {"time", "U(0, clip duration)"}};
  }
};

}  // namespace

extern const RandomizerEntry kNonTagAnimationRandomizer = {
    "NonTagAnimation",
    "Gives every person a clip drawn uniformly from the one pool of seated clips (the built-in "
    "library, a `--motions` folder, or the clips a `--clips-from` ranking keeps) and a time "
    "U(0, duration); the pose is the clip's frame at that time. Root motion is not applied. In "
    "the built-in pushing clips (push_rims_forward/backward, turn_in_place, turn_while_rolling, "
    "wheelie, extreme_ramp_drop) the arms are bent by IK so that the wrists meet the push rims "
    "of manual and sport chairs.",
    true, [](const ConfigNode* c) -> std::unique_ptr<Randomizer> {
      return std::make_unique<NonTagAnimation>(c);
    }};

}  // namespace wheelpose::generate
