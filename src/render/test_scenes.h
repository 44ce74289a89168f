#pragma once
// Small fixed scenes shared by the renderer's tests and the example scene files: each is a pure
// function of its name, so golden images can be regenerated.

#include <string>
#include <vector>

#include "scene/primitives.h"
#include "scene/scene.h"

namespace wheelpose::render::testing {

inline scene::Instance place(int mesh, int material, const Eigen::Vector3f& at, std::uint16_t id,
                             std::uint16_t semantic) {
  scene::Instance in;
  in.name = "object" + std::to_string(id);
  in.mesh = mesh;
  in.material = material;
  in.transform.topRightCorner<3, 1>() = at;
  in.instance_id = id;
  in.semantic_id = semantic;
  return in;
}

// Camera at the origin looking down −Z, 64×48, no lights: tests add what they need.
inline scene::Scene empty_scene(int width = 64, int height = 48) {
  scene::Scene s;
  s.camera.position = Eigen::Vector3f::Zero();
  s.camera.width = width;
  s.camera.height = height;
  s.camera.vfov_deg = 45.0f;
  s.sun.enabled = false;
  s.background.color = Eigen::Vector3f(0.05f, 0.06f, 0.08f);
  return s;
}

inline scene::Material material(const Eigen::Vector3f& diffuse, float specular = 0.0f) {
  scene::Material m;
  m.diffuse = diffuse;
  m.specular = specular;
  return m;
}

// A sphere on a floor lit by the sun, one point light and a uniform sky.
inline scene::Scene lit_sphere() {
  scene::Scene s = empty_scene();
  s.camera.position = Eigen::Vector3f(0, 1, 4);
  s.camera.orientation = Eigen::Quaternionf(Eigen::AngleAxisf(-0.25f, Eigen::Vector3f::UnitX()));
  s.meshes.push_back(scene::make_sphere(1.0f, 24));
  s.meshes.push_back(scene::make_plane(6, 6, 1));
  s.materials.push_back(material({0.8f, 0.25f, 0.2f}, 0.5f));
  s.materials.push_back(material({0.6f, 0.6f, 0.6f}));
  s.instances.push_back(place(0, 0, {0, 0, -1}, 1, 1));
  s.instances.push_back(place(1, 1, {0, -1, -1}, 2, 2));
  s.sun.enabled = true;
  s.sun.direction = Eigen::Vector3f(0.5f, 1.0f, 0.6f).normalized();
  s.point_lights.push_back({{-2, 1.5f, 1}, {0.4f, 0.6f, 1.0f}, 2.0f, 0.1f, true});
  s.environment = scene::Environment{};
  s.environment->color = Eigen::Vector3f(0.15f, 0.18f, 0.25f);
  return s;
}

// A floor and a wall with procedural and hue-shifted textures.
inline scene::Scene textured_plane() {
  scene::Scene s = empty_scene();
  s.camera.position = Eigen::Vector3f(0, 1.5f, 3);
  s.camera.orientation = Eigen::Quaternionf(Eigen::AngleAxisf(-0.35f, Eigen::Vector3f::UnitX()));
  s.meshes.push_back(scene::make_plane(3, 3, 1));
  scene::Material checker = material({1, 1, 1});
  checker.texture.kind = scene::TextureKind::kChecker;
  checker.texture.scale = 6;
  s.materials.push_back(checker);
  scene::Material wood = material({1, 1, 1});
  wood.texture.kind = scene::TextureKind::kWood;
  wood.texture.color_a = {0.55f, 0.35f, 0.18f};
  wood.texture.color_b = {0.25f, 0.12f, 0.05f};
  wood.texture.scale = 2;
  wood.hue_offset_deg = 120;
  s.materials.push_back(wood);
  s.instances.push_back(place(0, 0, {0, 0, -1}, 1, 1));
  scene::Instance wall = place(0, 1, {0, 1.5f, -3}, 2, 1);
  wall.transform.topLeftCorner<3, 3>() =
      Eigen::AngleAxisf(1.5707963f, Eigen::Vector3f::UnitX()).toRotationMatrix();
  s.instances.push_back(wall);
  s.sun.enabled = true;
  s.sun.direction = Eigen::Vector3f(0.2f, 1.0f, 0.8f).normalized();
  s.background.texture.kind = scene::TextureKind::kMarble;
  s.background.texture.scale = 4;
  return s;
}

// A box casting a soft shadow on a floor from a low sun and a point light.
inline scene::Scene shadow() {
  scene::Scene s = empty_scene();
  s.camera.position = Eigen::Vector3f(0, 3, 3);
  s.camera.orientation = Eigen::Quaternionf(Eigen::AngleAxisf(-0.8f, Eigen::Vector3f::UnitX()));
  s.meshes.push_back(scene::make_plane(4, 4, 1));
  s.meshes.push_back(scene::make_box({0.4f, 0.4f, 0.4f}, 1));
  s.materials.push_back(material({0.8f, 0.8f, 0.8f}));
  s.materials.push_back(material({0.2f, 0.5f, 0.8f}));
  s.instances.push_back(place(0, 0, {0, 0, 0}, 1, 1));
  s.instances.push_back(place(1, 1, {0, 0.4f, 0}, 2, 2));
  s.sun.enabled = true;
  s.sun.direction = Eigen::Vector3f(-1.0f, 0.8f, 0.3f).normalized();
  s.sun.angular_radius_deg = 3.0f;
  s.sun.intensity = 0.6f;
  s.point_lights.push_back({{1.5f, 1.5f, 1.0f}, {1.0f, 0.8f, 0.5f}, 1.5f, 0.2f, true});
  s.point_lights.push_back({{0, 5, 0}, {1, 1, 1}, 100.0f, 0.2f, false});  // off: no effect
  return s;
}

// Three spheres at 2, 4 and 8 m with the lens focused on the middle one.
inline scene::Scene depth_of_field() {
  scene::Scene s = empty_scene();
  s.meshes.push_back(scene::make_sphere(0.4f, 16));
  s.materials.push_back(material({0.9f, 0.3f, 0.2f}));
  s.materials.push_back(material({0.2f, 0.9f, 0.3f}));
  s.materials.push_back(material({0.2f, 0.3f, 0.9f}));
  s.instances.push_back(place(0, 0, {-0.6f, 0, -2}, 1, 1));
  s.instances.push_back(place(0, 1, {0, 0, -4}, 2, 1));
  s.instances.push_back(place(0, 2, {2.0f, 0, -8}, 3, 1));
  s.sun.enabled = true;
  s.sun.direction = Eigen::Vector3f(0.3f, 0.6f, 1.0f).normalized();
  s.camera.aperture_radius = 0.15f;
  s.camera.focus_distance = 4.0f;
  s.background.texture.kind = scene::TextureKind::kChecker;
  s.background.texture.scale = 8;
  s.background.texture.color_a = {0.3f, 0.3f, 0.3f};
  s.background.texture.color_b = {0.05f, 0.05f, 0.05f};
  return s;
}

// The lit sphere through every post effect at once.
inline scene::Scene post_effects() {
  scene::Scene s = lit_sphere();
  s.post.exposure_ev = 0.5f;
  s.post.temperature = 40;
  s.post.contrast = 20;
  s.post.saturation = -30;
  s.post.vignette = 0.6f;
  s.post.bloom = 0.5f;
  s.post.bloom_threshold = 0.6f;
  s.post.film_grain = 0.3f;
  s.post.lens_blur = 3.0f;
  s.camera.focus_distance = 4.0f;
  return s;
}

struct NamedScene {
  const char* name;
  scene::Scene (*make)();
};

inline std::vector<NamedScene> golden_scenes() {
  return {{"lit_sphere", lit_sphere},
          {"textured_plane", textured_plane},
          {"shadow", shadow},
          {"dof", depth_of_field},
          {"post", post_effects}};
}

}  // namespace wheelpose::render::testing
