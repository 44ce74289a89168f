#pragma once
// Pinhole projection of the scene camera (no lens): world → camera space → pixel coordinates,
// matching the renderer's primary rays through pixel centres (pixel (x, y) covers
// [x, x + 1) × [y, y + 1); square pixels).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

#include "scene/scene.h"

namespace wheelpose::scene {

struct Projector {
  Eigen::Matrix3f world_to_camera_rotation;
  Eigen::Vector3f camera_position;
  float f, cx, cy;  // focal length in pixels, principal point
  int width, height;

  explicit Projector(const Camera& cam)
      : world_to_camera_rotation(cam.orientation.normalized().toRotationMatrix().transpose()),
        camera_position(cam.position),
        f(0.5f * static_cast<float>(cam.height) / std::tan(0.5f * cam.effective_vfov())),
        cx(0.5f * static_cast<float>(cam.width)),
        cy(0.5f * static_cast<float>(cam.height)),
        width(cam.width),
        height(cam.height) {}

  Eigen::Vector3f to_camera(const Eigen::Vector3f& world) const {
    return world_to_camera_rotation * (world - camera_position);
  }
  // Pixel coordinates of a camera-space point in front of the camera (z < 0).
  Eigen::Vector2f project(const Eigen::Vector3f& c) const {
    return Eigen::Vector2f(cx + f * c.x() / -c.z(), cy - f * c.y() / -c.z());
  }
};

}  // namespace wheelpose::scene
