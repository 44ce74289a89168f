// HumanGeneration: a pool of generated people, regenerated periodically; a random subset of it
// appears in each frame.

#include <algorithm>
#include <numeric>
#include <string>
#include <vector>

#include "core/error.h"
#include "generate/garment_palette.h"
#include "generate/randomizer.h"

namespace wheelpose::generate {
namespace {

// MakeHuman blends three ancestries; the paper's five groups as shares of them.
struct Ethnicity {
  const char* name;
  double african, asian, caucasian;
};
constexpr Ethnicity kEthnicities[] = {{"caucasian", 0.0, 0.0, 1.0},
                                      {"asian", 0.0, 1.0, 0.0},
                                      {"latin_american", 0.2, 0.3, 0.5},
                                      {"african", 1.0, 0.0, 0.0},
                                      {"middle_eastern", 0.15, 0.15, 0.7}};

GarmentColours garment_colours_of(const ConfigNode* c) {
  return choice_or(c, "garment_colours", "palette", {"palette", "uniform"}) == "palette"
             ? GarmentColours::kPalette
             : GarmentColours::kUniform;
}

// `exclude_assets`: MakeHuman asset names ("clothes/…", "hair/…") never drawn, so a test set can
// hold clothes and hair a training set never saw.
std::vector<std::string> asset_list(const ConfigNode* c, const std::string& key) {
  std::vector<std::string> names;
  if (c == nullptr || !c->has(key)) return names;
  const ConfigNode list = c->child(key);
  if (!list.is_sequence()) list.fail("must be a list of asset names such as hair/bob01");
  for (std::size_t i = 0; i < list.size(); ++i) {
    const ConfigNode item = list.element(i);
    const std::string name = item.as_string();
    if (name.find('/') == std::string::npos) item.fail("'" + name + "' is not <folder>/<name>");
    names.push_back(name);
  }
  std::sort(names.begin(), names.end());
  return names;
}

class HumanGeneration final : public Randomizer {
 public:
  explicit HumanGeneration(const ConfigNode* c)
      : pool_size_(integer_or(c, "pool_size", 50, 1, 100000)),
        refresh_(integer_or(c, "pool_refresh_frames", 400, 1, 1LL << 40)),
        min_count_(integer_or(c, "min_per_frame", 5, 0, 1000)),
        max_count_(integer_or(c, "max_per_frame", 12, 0, 1000)),
        age_(sampler_or(c, "age", ScalarSampler::uniform(10, 100), 1, 120)),
        height_(sampler_or(c, "height", ScalarSampler::uniform(0.1, 1), 0, 1)),
        weight_(sampler_or(c, "weight", ScalarSampler::uniform(0, 1), 0, 1)),
        gender_(sampler_or(c, "gender", ScalarSampler::categorical({0.0, 1.0}, {1, 1}), 0, 1)),
        clothing_(number_or(c, "clothing_probability", 1.0, 0.0, 1.0)),
        hair_(number_or(c, "hair_probability", 0.85, 0.0, 1.0)),
        hat_(number_or(c, "hat_probability", 0.1, 0.0, 1.0)),
        strand_coverage_(number_or(c, "hair_strand_coverage", 0.6, 0.05, 1.0)),
        excluded_(asset_list(c, "exclude_assets")),
        garment_colours_(garment_colours_of(c)) {
    if (max_count_ < min_count_) c->fail("max_per_frame is below min_per_frame");
  }

  void apply(FrameDraft& f, RandomStream& rng, const RandomizerContext& ctx) const override {
    const std::int64_t pool = f.index / refresh_;
    const std::int64_t count =
        std::min<std::int64_t>(rng.uniform_int(min_count_, max_count_), pool_size_);
    std::vector<int> slots(static_cast<std::size_t>(pool_size_));
    std::iota(slots.begin(), slots.end(), 0);
    for (std::int64_t i = 0; i < count; ++i) {  // partial Fisher–Yates
      std::swap(slots[i], slots[rng.uniform_int(i, pool_size_ - 1)]);
    }
    for (std::int64_t i = 0; i < count; ++i) {
      PersonDraft p;
      p.pool_slot = slots[i];
      // A pool member is a pure function of (seed, pool, slot): the same person in every frame
      // of the pool, whichever frames a shard renders.
      RandomStream member(f.seed, {"pool", static_cast<std::uint64_t>(pool), p.pool_slot});
      p.spec = body::sample_spec(member.next_u64());
      p.spec.limbs = {};  // LimbDifference decides
      body::MacroParams& m = p.spec.params;
      m.age_years = age_.sample(member);
      m.height = height_.sample(member);
      m.weight = weight_.sample(member);
      m.gender = gender_.sample(member);
      const Ethnicity& e = kEthnicities[member.uniform_int(0, 4)];
      m.african = e.african;
      m.asian = e.asian;
      m.caucasian = e.caucasian;
      const double tone = 0.12 * e.african + 0.6 * e.asian + 0.8 * e.caucasian;
      m.skin_tone = std::clamp(tone + member.normal(0.0, 0.08), 0.0, 1.0);
      p.outfit.top = garment_material(member, "top", garment_colours_);
      p.outfit.bottom = garment_material(member, "bottom", garment_colours_);
      p.outfit.shoes = garment_material(member, "shoes", garment_colours_);
      p.outfit.shoes.texture.kind = scene::TextureKind::kNone;
      p.outfit.shoes.diffuse = p.outfit.shoes.texture.color_a * 0.5f;
      p.outfit.long_sleeves = member.bernoulli(0.6);
      p.outfit.long_trousers = member.bernoulli(0.8);
      // MakeHuman clothes, shoes, hair and eyebrows (CC0 proxies fitted to the body).
      const bool clothed = member.bernoulli(clothing_);
      const bool has_hair = member.bernoulli(hair_);
      const bool has_hat = member.bernoulli(hat_);
      const body::ProxyCatalog filtered =
          excluded_.empty() ? body::ProxyCatalog{} : allowed(ctx.proxies);
      const body::ProxyCatalog& kit = excluded_.empty() ? ctx.proxies : filtered;
      const auto& male = kit.male_suits;
      const auto& female = kit.female_suits;
      const std::string suit =
          body::pick_proxy(member, m.gender >= 0.5 ? (male.empty() ? female : male)
                                                   : (female.empty() ? male : female));
      const std::string shoe = body::pick_proxy(member, kit.shoes);
      const std::string hat = body::pick_proxy(member, kit.hats);
      const std::string hair = body::pick_proxy(member, kit.hair);
      const std::string brows = body::pick_proxy(member, kit.eyebrows);
      if (clothed) {
        for (const std::string* proxy : {&suit, &shoe}) {
          if (!proxy->empty()) p.spec.proxies.push_back(*proxy);
        }
      }
      if (has_hair && !hair.empty() && !(has_hat && !hat.empty())) p.spec.proxies.push_back(hair);
      if (has_hat && !hat.empty()) p.spec.proxies.push_back(hat);
      if (!brows.empty()) p.spec.proxies.push_back(brows);
      // Eyes: the low-poly eyeballs (the assets' textures are absent, so an iris colour).
      const auto eyes = std::find(kit.eyes.begin(), kit.eyes.end(), "eyes/low-poly");
      if (eyes != kit.eyes.end()) p.spec.proxies.push_back(*eyes);
      const double iris = member.uniform01();
      p.outfit.eyes.name = "eyes";
      p.outfit.eyes.diffuse = iris < 0.6   ? Eigen::Vector3f(0.12f, 0.06f, 0.03f)
                              : iris < 0.8 ? Eigen::Vector3f(0.15f, 0.25f, 0.4f)
                                           : Eigen::Vector3f(0.15f, 0.25f, 0.12f);
      p.outfit.eyes.specular = 0.6f;
      p.outfit.eyes.shininess = 80.0f;
      const double shade = member.uniform01();
      p.outfit.hair.name = "hair";
      p.outfit.hair.diffuse = shade < 0.45   ? Eigen::Vector3f(0.05f, 0.035f, 0.025f)
                              : shade < 0.7  ? Eigen::Vector3f(0.25f, 0.14f, 0.07f)
                              : shade < 0.85 ? Eigen::Vector3f(0.65f, 0.5f, 0.3f)
                                             : Eigen::Vector3f(0.6f, 0.6f, 0.6f);
      if (m.age_years > 60 && member.bernoulli(0.6))
        p.outfit.hair.diffuse = Eigen::Vector3f(0.7f, 0.7f, 0.7f);
      p.outfit.hair.specular = 0.15f;
      if (strand_coverage_ < 1)
        cut_into_strands(p.outfit.hair, static_cast<float>(strand_coverage_));
      f.people.push_back(std::move(p));
    }
  }

  nlohmann::ordered_json parameters() const override {
    nlohmann::ordered_json out = {
        {"pool_size", pool_size_},
        {"pool_refresh_frames", refresh_},
        {"min_per_frame", min_count_},
        {"max_per_frame", max_count_},
        {"age", age_.describe()},
        {"height", height_.describe()},
        {"weight", weight_.describe()},
        {"gender", gender_.describe()},
        {"clothing_probability", clothing_},
        {"hair_probability", hair_},
        {"hat_probability", hat_},
        {"hair_strand_coverage", strand_coverage_},
        {"garment_colours", garment_colours_ == GarmentColours::kPalette ? "palette" : "uniform"}};
    if (!excluded_.empty()) out["exclude_assets"] = excluded_;  // absent: earlier files unchanged
    return out;
  }

 private:
  // The installed proxies less the excluded ones (each of which must be installed); a copy
  // per frame, a few dozen names.
  body::ProxyCatalog allowed(const body::ProxyCatalog& kit) const {
    body::ProxyCatalog out = kit;
    for (const std::string& name : excluded_) {
      bool found = false;
      for (auto* list : {&out.male_suits, &out.female_suits, &out.shoes, &out.hats, &out.hair,
                         &out.eyebrows, &out.eyes}) {
        const auto at = std::find(list->begin(), list->end(), name);
        if (at != list->end()) list->erase(at), found = true;
      }
      if (!found) {
        throw Error("HumanGeneration.exclude_assets: '" + name +
                    "' is not an installed MakeHuman asset");
      }
    }
    return out;
  }

  long long pool_size_, refresh_, min_count_, max_count_;
  ScalarSampler age_, height_, weight_, gender_;
  double clothing_, hair_, hat_, strand_coverage_;
  std::vector<std::string> excluded_;
  GarmentColours garment_colours_;
};

}  // namespace

extern const RandomizerEntry kHumanGenerationRandomizer = {
    "HumanGeneration",
    "Keeps a pool of `pool_size` = 50 MakeHuman people, regenerated every `pool_refresh_frames` "
    "= 400 frames, and shows `min_per_frame`…`max_per_frame` = 5…12 of them (uniform integer, "
    "both ends included as the paper's table says; the authors' integer cast gave 5…11). Each "
    "person: `age` U(10, 100) years (MakeHuman's scale stops at 90), `height` U(0.1, 1) and "
    "`weight` U(0, 1) (normalised sliders), `gender` female/male, ethnicity uniform over the "
    "paper's five groups as blends of MakeHuman's African/Asian/Caucasian targets (Latin American "
    "0.2/0.3/0.5, Middle Eastern 0.15/0.15/0.7), skin tone from the blend ± N(0, 0.08), muscle and "
    "proportions as `wheelpose body sample`. Clothing: with `clothing_probability` = 1 a "
    "MakeHuman CC0 suit for the person's sex and shoes, fitted through their `.mhclo` proxies "
    "(the skin they cover is hidden), the suit cut by nearest bone into a top and a bottom; "
    "`garment_colours` = palette draws each garment's colour from everyday clothing shades "
    "(four fifths muted: black, greys, white, cream, beige, browns, navy, denims, olive, "
    "burgundy; a fifth saturated), jittered, as a plain weave (0.6; half of them the weave and "
    "folds of one of four CC0 fabric photos of sweethome3d-furniture's BlendSwap catalogue, in "
    "that colour), heather (0.2), stripes "
    "(0.12) or checks (0.08); `uniform` is the earlier draw, each channel U(0.03, 0.9) with half "
    "the garments striped, checked or mottled (the assets carry no textures); `hair_probability` = "
    "0.85 one of the hair proxies (dark, "
    "brown, blond or grey; older people greyer) drawn as alpha cards of strands covering "
    "`hair_strand_coverage` = 0.6 of each card layer (1 = the opaque helmet of earlier versions), "
    "`hat_probability` = 0.1 a hat instead, and "
    "eyebrows (strands too) and low-poly eyes (an iris colour: the assets' textures are absent). "
    "`exclude_assets` "
    "(a list such as [hair/bob01, clothes/male_worksuit01]) is never drawn: hold clothes and hair "
    "out of a training set. Without proxies (or with `clothing_probability` 0) the body itself is "
    "painted "
    "as top, bottom and shoes by nearest bone, with long or short sleeves (0.6) and trousers "
    "(0.8).",
    true, [](const ConfigNode* c) -> std::unique_ptr<Randomizer> {
      return std::make_unique<HumanGeneration>(c);
    }};

}  // namespace wheelpose::generate
