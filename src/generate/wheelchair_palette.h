#pragma once
// What a wheelchair is painted: frame, upholstery, tyres and trim. The palette draws what chairs
// are sold in — frames mostly black, silver or graphite, about a third anodised in a colour;
// upholstery nearly always black, charcoal or navy; silver or black trim — each shade jittered.
// `kUniform` is the earlier draw (frame U(0.05, 0.9), upholstery U(0.02, 0.4), trim U(0.3, 0.8)
// per channel), whose green and magenta chairs a photo-trained model has never seen.

#include <Eigen/Core>
#include <array>
#include <vector>

#include "core/config.h"
#include "core/random.h"

namespace wheelpose::generate {

enum class ChairColours { kPalette, kUniform };

// Linear RGB of the chair's materials in body::Wheelchair's order: frame, upholstery, tyre, trim.
using ChairPaint = std::array<Eigen::Vector3f, 4>;

ChairPaint wheelchair_colours(RandomStream& rng, ChairColours style);

// A randomizer's `colours` key: palette (absent) or uniform; anything else fails naming the key.
ChairColours chair_colours_of(const ConfigNode* config);
const char* chair_colours_name(ChairColours style);

// A palette entry, linear RGB, for tests.
struct ChairShade {
  const char* name;
  Eigen::Vector3f colour;
  double weight;  // relative, within its part's list
};
const std::vector<ChairShade>& frame_shades();
const std::vector<ChairShade>& upholstery_shades();
const std::vector<ChairShade>& trim_shades();

}  // namespace wheelpose::generate
