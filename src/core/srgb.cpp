#include "core/srgb.h"

#include <algorithm>
#include <cmath>

namespace wheelpose {

float srgb_to_linear(float c) {
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

float linear_to_srgb(float c) {
  c = std::clamp(c, 0.0f, 1.0f);
  return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

Eigen::Vector3f linear_from_srgb_hex(unsigned rgb) {
  const auto channel = [&](int shift) {
    return srgb_to_linear(static_cast<float>((rgb >> shift) & 0xff) / 255.0f);
  };
  return {channel(16), channel(8), channel(0)};
}

}  // namespace wheelpose
