// Portrait scene of one person, built with the generator's frame builder and rendered.

#include "generate/portrait.h"

#include <cmath>

#include "core/keypoint_template.h"
#include "core/random.h"
#include "generate/frame_builder.h"
#include "render/renderer.h"

namespace wheelpose::generate {
namespace {

scene::Material plain(const Eigen::Vector3f& colour,
                      scene::TextureKind kind = scene::TextureKind::kNone) {
  scene::Material m;
  m.diffuse = Eigen::Vector3f::Ones();
  m.texture.kind = kind == scene::TextureKind::kNone ? scene::TextureKind::kNone : kind;
  m.texture.color_a = colour;
  m.texture.color_b = colour * 0.7f;
  m.texture.scale = 20;
  if (kind == scene::TextureKind::kNone) m.diffuse = colour;
  return m;
}

}  // namespace

cv::Mat render_portrait(const body::BodyData& data, const body::PersonSpec& spec, int size,
                        int spp) {
  FrameDraft draft;
  draft.environment = EnvironmentKind::kWall;
  draft.wall = plain(Eigen::Vector3f(0.55f, 0.56f, 0.58f));
  draft.wall_z = -2.0f;
  PersonDraft person;
  person.spec = spec;
  RandomStream colours(spec.seed, {"portrait"});
  auto colour = [&colours] {
    return Eigen::Vector3f(static_cast<float>(colours.uniform(0.08, 0.8)),
                           static_cast<float>(colours.uniform(0.08, 0.8)),
                           static_cast<float>(colours.uniform(0.08, 0.8)));
  };
  person.outfit.top = plain(colour(), scene::TextureKind::kFabric);
  person.outfit.bottom = plain(Eigen::Vector3f(0.25f, 0.25f, 0.28f), scene::TextureKind::kFabric);
  person.outfit.shoes = plain(Eigen::Vector3f(0.08f, 0.06f, 0.05f));
  person.outfit.hair = plain(Eigen::Vector3f(0.12f, 0.08f, 0.05f));
  cut_into_strands(person.outfit.hair, 0.6f);
  person.outfit.eyes = plain(Eigen::Vector3f(0.1f, 0.06f, 0.03f));
  person.rotation = Eigen::AngleAxisf(0.5f, Eigen::Vector3f::UnitY());
  person.placed = true;
  draft.people.push_back(person);
  draft.camera.position = Eigen::Vector3f(0.0f, 0.15f, 2.9f);
  draft.camera.vfov_deg = 36.0f;
  draft.camera.width = draft.camera.height = size;
  draft.sun.direction = Eigen::Vector3f(0.4f, 0.8f, 0.6f).normalized();
  draft.sun.intensity = 0.9f;
  draft.sun.angular_radius_deg = 1.0f;
  scene::Environment sky;
  sky.color = Eigen::Vector3f(0.3f, 0.32f, 0.35f);
  draft.sky = sky;
  static const std::vector<KeypointAnchor> anchors =
      resolve_anchors(load_keypoint_template("coco17"));
  const BuiltFrame built = build_frame(draft, data, {}, anchors);
  render::Renderer renderer(built.scene);
  render::RenderOptions options;
  options.spp = spp;
  options.post = false;
  return renderer.render(options).rgb;
}

}  // namespace wheelpose::generate
