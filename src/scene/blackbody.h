#pragma once
// The colour of a black-body (Planckian) radiator, for lights: warm bulbs near 2,700 K, daylight
// near 6,500 K. Chromaticity from the cubic-spline fit of the Planckian locus by Kim et al.
// (2002), valid from 1,667 K to 25,000 K; to linear sRGB (D65) by the IEC 61966-2-1 matrix.

#include <Eigen/Core>

namespace wheelpose::scene {

inline constexpr double kMinColourTemperature = 1667, kMaxColourTemperature = 25000;

// Linear sRGB of a black body at `kelvin` (clamped to the fit's range), scaled so that its
// largest channel is 1; channels the sRGB gamut cannot hold are clipped at 0.
Eigen::Vector3f blackbody_rgb(double kelvin);

}  // namespace wheelpose::scene
