#pragma once
// What people wear: the fabric of a top, a bottom or shoes. The realistic palette draws from the
// colours clothes are mostly sold in (muted: blacks, greys, whites, creams, browns, navies,
// denims, olives) with a fifth saturated (red, mustard, teal, royal blue, pink, …), each shade
// jittered, on a plain weave mostly and sometimes stripes, checks or a heather; `kUniform` is
// the earlier draw (each channel U(0.03, 0.9), half the garments patterned).

#include <string>
#include <vector>

#include "core/random.h"
#include "scene/scene.h"

namespace wheelpose::generate {

enum class GarmentColours { kPalette, kUniform };

// Of the palette's garments, the share drawn as a photographed fabric (half the plain weaves):
// the brightness detail (render::load_detail_image) of a CC0 fabric photo from the BlendSwap
// catalogue of Debian's sweethome3d-furniture, in the garment's colour.
inline constexpr double kPhotoFabricShare = 0.3;
// The photos, as "ARCHIVE!/ENTRY" paths (core/archive_member.h).
const std::vector<std::string>& fabric_photos();

scene::Material garment_material(RandomStream& rng, const std::string& name, GarmentColours style);

// Palette shades, linear RGB, for tests: muted first, then saturated.
struct GarmentShade {
  const char* name;
  float r, g, b;  // linear
  bool saturated;
};
const std::vector<GarmentShade>& garment_palette();

}  // namespace wheelpose::generate
