#pragma once
// What people wear: the fabric of a top, a bottom or shoes. The realistic palette draws from the
// colours clothes are mostly sold in (muted: blacks, greys, whites, creams, browns, navies,
// denims, olives) with a fifth saturated (red, mustard, teal, royal blue, pink, …), each shade
// jittered, on a plain weave mostly and sometimes stripes, checks or a heather; `kUniform` is
// the earlier draw (each channel U(0.03, 0.9), half the garments patterned).

#include <string>

#include "core/random.h"
#include "scene/scene.h"

namespace wheelpose::generate {

enum class GarmentColours { kPalette, kUniform };

scene::Material garment_material(RandomStream& rng, const std::string& name, GarmentColours style);

// Palette shades, linear RGB, for tests: muted first, then saturated.
struct GarmentShade {
  const char* name;
  float r, g, b;  // linear
  bool saturated;
};
const std::vector<GarmentShade>& garment_palette();

}  // namespace wheelpose::generate
