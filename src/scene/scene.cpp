#include "scene/scene.h"

#include <cmath>
#include <filesystem>
#include <numbers>

namespace wheelpose::scene {
namespace {
constexpr float kDeg = std::numbers::pi_v<float> / 180.0f;
}  // namespace

float Camera::effective_vfov() const {
  if (focal_length_mm > 0.0f) return 2.0f * std::atan(sensor_height_mm / (2.0f * focal_length_mm));
  return vfov_deg * kDeg;
}

// Solar position from local solar time, day of year and latitude (no equation of time, no
// refraction: good to about a degree, which is all a randomizer needs):
//   declination  δ = −23.44° · cos(2π · (day + 10) / 365)
//   hour angle   H = 15° · (hour − 12)            (negative in the morning)
//   toward the sun in east/north/up coordinates:
//     east  = −cos δ · sin H
//     north =  sin δ · cos φ − cos δ · sin φ · cos H
//     up    =  sin δ · sin φ + cos δ · cos φ · cos H      (= sin of the elevation)
// World axes: east = +X, up = +Y, north = −Z.
Eigen::Vector3f solar_direction(const SolarPosition& s) {
  const double pi = std::numbers::pi;
  const double decl = -23.44 * pi / 180.0 * std::cos(2.0 * pi * (s.day_of_year + 10.0) / 365.0);
  const double h = 15.0 * (s.hour - 12.0) * pi / 180.0;
  const double phi = s.latitude_deg * pi / 180.0;
  const double east = -std::cos(decl) * std::sin(h);
  const double north =
      std::sin(decl) * std::cos(phi) - std::cos(decl) * std::sin(phi) * std::cos(h);
  const double up = std::sin(decl) * std::sin(phi) + std::cos(decl) * std::cos(phi) * std::cos(h);
  return Eigen::Vector3f(static_cast<float>(east), static_cast<float>(up),
                         static_cast<float>(-north))
      .normalized();
}

Eigen::Vector3f sun_direction(const Sun& sun) {
  if (sun.solar) return solar_direction(*sun.solar);
  return sun.direction.normalized();
}

std::string resolve_path(const Scene& scene, const std::string& path) {
  const std::filesystem::path p(path);
  if (p.is_absolute() || scene.base_dir.empty()) return path;
  return (std::filesystem::path(scene.base_dir) / p).string();
}

}  // namespace wheelpose::scene
