#include "generate/wheelchair_palette.h"

#include "core/srgb.h"
#include "generate/randomizer.h"

namespace wheelpose::generate {
namespace {

struct Swatch {
  const char* name;
  unsigned rgb;  // sRGB, 0xRRGGBB
  double weight;
};

std::vector<ChairShade> shades_of(std::initializer_list<Swatch> swatches) {
  std::vector<ChairShade> out;
  for (const Swatch& s : swatches) out.push_back({s.name, linear_from_srgb_hex(s.rgb), s.weight});
  return out;
}

// A shade drawn by weight, its brightness and each channel jittered a little.
Eigen::Vector3f draw_shade(RandomStream& rng, const std::vector<ChairShade>& shades) {
  double total = 0;
  for (const ChairShade& s : shades) total += s.weight;
  double u = rng.uniform(0, total);
  const ChairShade* pick = &shades.back();
  for (const ChairShade& s : shades) {
    if (u < s.weight) {
      pick = &s;
      break;
    }
    u -= s.weight;
  }
  const float brightness = static_cast<float>(rng.uniform(0.85, 1.15));
  Eigen::Vector3f c = pick->colour;
  for (int i = 0; i < 3; ++i) c[i] *= brightness * static_cast<float>(rng.uniform(0.96, 1.04));
  return c.cwiseMin(0.95f);
}

// Blue first, then green, then red: the order the earlier code's constructor arguments were
// evaluated in (GCC's), so `colours: uniform` draws the very chairs it drew.
Eigen::Vector3f uniform_colour(RandomStream& rng, double lo, double hi) {
  const float b = static_cast<float>(rng.uniform(lo, hi));
  const float g = static_cast<float>(rng.uniform(lo, hi));
  const float r = static_cast<float>(rng.uniform(lo, hi));
  return {r, g, b};
}

}  // namespace

// Shades chosen here by looking at what manual, sport and power chairs are sold in (no
// catalogue's numbers): powder-coated or anodised tubes, black sling or cushion fabric.
const std::vector<ChairShade>& frame_shades() {
  static const std::vector<ChairShade> shades = shades_of({
      {"black", 0x1e1f21, 0.25},
      {"silver", 0xa9adb2, 0.22},
      {"graphite", 0x4a4d52, 0.13},
      {"white", 0xdedfe0, 0.04},
      {"red", 0xa3232b, 0.06},
      {"blue", 0x27459a, 0.06},
      {"purple", 0x5a2f7a, 0.04},
      {"green", 0x2f7d45, 0.04},
      {"orange", 0xd0651e, 0.03},
      {"pink", 0xc9618f, 0.03},
      {"teal", 0x1d7377, 0.03},
      {"yellow", 0xd3b02a, 0.02},
      {"wine", 0x5c1a27, 0.03},
      {"bronze", 0x7a5a3a, 0.02},
  });
  return shades;
}

const std::vector<ChairShade>& upholstery_shades() {
  static const std::vector<ChairShade> shades = shades_of({
      {"black", 0x141416, 0.62},
      {"charcoal", 0x2e3034, 0.2},
      {"navy", 0x1b2238, 0.1},
      {"burgundy", 0x45181f, 0.03},
      {"dark green", 0x1f3326, 0.025},
      {"dark blue", 0x1f3566, 0.025},
  });
  return shades;
}

const std::vector<ChairShade>& trim_shades() {
  static const std::vector<ChairShade> shades = shades_of({
      {"chrome", 0xb4b7ba, 0.45},
      {"aluminium", 0x8d9094, 0.25},
      {"black", 0x1e1f21, 0.3},
  });
  return shades;
}

ChairColours chair_colours_of(const ConfigNode* config) {
  return choice_or(config, "colours", "palette", {"palette", "uniform"}) == "palette"
             ? ChairColours::kPalette
             : ChairColours::kUniform;
}

const char* chair_colours_name(ChairColours style) {
  return style == ChairColours::kPalette ? "palette" : "uniform";
}

ChairPaint wheelchair_colours(RandomStream& rng, ChairColours style) {
  if (style == ChairColours::kUniform) {
    // The earlier draw, in its order (the tyre first).
    const float tyre = static_cast<float>(rng.uniform(0.02, 0.12));
    const Eigen::Vector3f frame = uniform_colour(rng, 0.05, 0.9);
    const Eigen::Vector3f upholstery = uniform_colour(rng, 0.02, 0.4);
    const Eigen::Vector3f trim = uniform_colour(rng, 0.3, 0.8);
    return {frame, upholstery, Eigen::Vector3f::Constant(tyre), trim};
  }
  const Eigen::Vector3f frame = draw_shade(rng, frame_shades());
  const Eigen::Vector3f upholstery = draw_shade(rng, upholstery_shades());
  const float tyre = static_cast<float>(rng.uniform(0.02, 0.12));
  const Eigen::Vector3f trim = draw_shade(rng, trim_shades());
  return {frame, upholstery, Eigen::Vector3f::Constant(tyre), trim};
}

}  // namespace wheelpose::generate
