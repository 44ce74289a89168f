#pragma once
// The sRGB transfer functions (IEC 61966-2-1), shared by the renderer (textures, encoding) and
// the colour tables written as sRGB swatches (skin, garments, interiors).

#include <Eigen/Core>

namespace wheelpose {

float srgb_to_linear(float c);  // encoded value in [0, 1] to linear light
float linear_to_srgb(float c);  // linear light, clamped to [0, 1], to the encoded value

// A colour written as 0xRRGGBB (8-bit sRGB), in linear light.
Eigen::Vector3f linear_from_srgb_hex(unsigned rgb);

}  // namespace wheelpose
