#include "render/strands.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "core/random.h"

namespace wheelpose::render {
namespace {

// A number in [0, 1) for a strand or strand bundle index.
float unit_hash(std::int64_t index, std::uint64_t salt) {
  const std::uint64_t h =
      StreamKey::mix(static_cast<std::uint64_t>(index) * 0x9e3779b97f4a7c15ULL ^ salt);
  return static_cast<float>(h >> 40) * (1.0f / 16777216.0f);
}

// A smooth periodic wave in [-1, 1] with period 1: parabolic arcs, no trigonometry.
float wave(float t) {
  const float f = t - std::floor(t);
  const float half = f < 0.5f ? f * 2 : (f - 0.5f) * 2;  // 0–1 over each half period
  const float arc = 4 * half * (1 - half);               // 0 → 1 → 0
  return f < 0.5f ? arc : -arc;
}

}  // namespace

StrandSample strand_at(float u, float v, float per_uv, float coverage) {
  // Bundles of ~8 strands wave together along their length, each bundle in its own phase.
  constexpr float kBundle = 8.0f;
  const float x = u * per_uv;
  const auto bundle = static_cast<std::int64_t>(std::floor(x / kBundle));
  const float waved = x + 0.6f * wave(v * 4.0f + unit_hash(bundle, 1));
  const auto strand = static_cast<std::int64_t>(std::floor(waved));
  const float across = waved - static_cast<float>(strand);  // 0–1 across the strand's cell
  // Widths vary ±40 % about the coverage; a strand never fills its cell, so gaps stay open.
  const float width = std::min(0.95f, coverage * (0.6f + 0.8f * unit_hash(strand, 2)));
  const float from_middle = std::abs(across - 0.5f) * 2;  // 0 in the middle, 1 at the cell edge
  StrandSample s;
  s.covered = from_middle < width;
  if (!s.covered) return s;
  const float edge = from_middle / width;  // 0 on the strand's axis, 1 at its edge
  s.shade = (0.75f + 0.4f * unit_hash(strand, 3)) * (1.0f - 0.3f * edge * edge);
  return s;
}

}  // namespace wheelpose::render
