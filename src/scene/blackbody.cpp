#include "scene/blackbody.h"

#include <algorithm>

namespace wheelpose::scene {

Eigen::Vector3f blackbody_rgb(double kelvin) {
  const double t = std::clamp(kelvin, kMinColourTemperature, kMaxColourTemperature);
  const double t1 = 1e3 / t, t2 = t1 * t1, t3 = t2 * t1;  // in thousands of kelvin, inverted
  const double x = t <= 4000 ? -0.2661239 * t3 - 0.2343589 * t2 + 0.8776956 * t1 + 0.179910
                             : -3.0258469 * t3 + 2.1070379 * t2 + 0.2226347 * t1 + 0.240390;
  const double x2 = x * x, x3 = x2 * x;
  double y;
  if (t <= 2222) {
    y = -1.1063814 * x3 - 1.34811020 * x2 + 2.18555832 * x - 0.20219683;
  } else if (t <= 4000) {
    y = -0.9549476 * x3 - 1.37418593 * x2 + 2.09137015 * x - 0.16748867;
  } else {
    y = 3.0817580 * x3 - 5.87338670 * x2 + 3.75112997 * x - 0.37001483;
  }
  // xyY with Y = 1 to XYZ, then to linear sRGB.
  const double cap_x = x / y, cap_y = 1, cap_z = (1 - x - y) / y;
  Eigen::Vector3d rgb(3.2406 * cap_x - 1.5372 * cap_y - 0.4986 * cap_z,
                      -0.9689 * cap_x + 1.8758 * cap_y + 0.0415 * cap_z,
                      0.0557 * cap_x - 0.2040 * cap_y + 1.0570 * cap_z);
  rgb = rgb.cwiseMax(0.0);
  return (rgb / rgb.maxCoeff()).cast<float>();
}

}  // namespace wheelpose::scene
