#pragma once
// Embree ray tracing of a Scene into frame buffers, and ray queries for the annotator.
//
// Build: every instance becomes one triangle geometry in a single flat Embree scene (world-space
// vertices; flat was faster than instancing in the spike), build quality LOW for the scene
// and for each geometry (MEDIUM traces rays ≈ 10 % faster, but with decoupled shading and
// adaptive anti-aliasing a frame traces too few rays to pay for its 3× slower build);
// geometry id = index into Scene::instances.
// Trace: TBB over 8×8-pixel tiles; each tile shoots 4×2-pixel packets (rtcIntersect8) per
// sample, then, for the samples that light (see RenderOptions), shadow packets (rtcOccluded8)
// for the sun, one sampled point light and the environment. Every random number comes from
// RandomStream(seed, {"pixel", index}), drawn in sample order, so the image is identical whatever
// the thread count or tile order.

#include <embree3/rtcore.h>

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <opencv2/core.hpp>
#include <vector>

#include "render/denoise.h"
#include "render/texture.h"
#include "scene/scene.h"

namespace wheelpose::render {

// Decoupled shading: every sample finds its surface and colour (anti-aliasing, depth of field,
// texture detail), but the lights are sampled only by the first `light_samples` samples of a
// pixel; the pixel's other samples on the same surface reuse that lighting with their own
// albedo (like MSAA), and samples on another surface (silhouettes, creases) are lit on their
// own. The per-pixel lighting is then smoothed over neighbouring pixels of the same surface
// (render/denoise.h). light_samples = spp with denoise_radius = 0 is brute-force sampling.
//
// Adaptive anti-aliasing: every pixel first takes its `light_samples` samples; only pixels
// whose 3×3 neighbourhood shows an edge in those first samples (another surface, a crease, a
// depth step, an albedo or background contrast above `adaptive_contrast`) or that lie along a
// triangle thinner than a pixel (render/adaptive.h) take the rest. A
// pixel so refined gets exactly the value a uniform render gives it, the others exactly the
// value of a render with spp = light_samples. Off with a lens (defocus blur needs every
// sample) and when adaptive_contrast < 0.
struct RenderOptions {
  static constexpr int kMaxSpp = 4096, kMaxDenoiseRadius = 16;
  int spp = 1;             // samples per pixel (anti-aliasing, depth of field)
  int light_samples = 1;   // of those, how many sample the lights (1 … spp)
  int denoise_radius = 3;  // lighting smoothing window (pixels; 0 = off)
  // Linear albedo (or background radiance) step between neighbouring pixels above which they
  // take every sample; < 0 = uniform sampling, every pixel takes spp samples.
  float adaptive_contrast = 0.05f;  // scenario image.adaptive_contrast
  bool post = true;                 // apply Scene::post; false gives the plain sRGB encoding
  // One diffuse bounce of the sun and point lights (light off walls, floors and people fills
  // the shadows); off, surfaces see direct light only. Adds a ray and up to two shadow rays
  // per light sample.
  bool bounce = false;

  // How the fields are spelled in messages: as a scenario's image section names them, or as
  // `wheelpose render`'s flags.
  struct Names {
    const char *spp, *light_samples, *denoise_radius, *adaptive_contrast;
  };
  static constexpr Names kScenarioNames{"spp", "light_samples", "denoise_radius",
                                        "adaptive_contrast"};
  // Every rule these options obey, held here once (Renderer::render, the scenario's image
  // section and `wheelpose render` all call it): throws Error naming the first field that
  // breaks one.
  void check(const Names& names = kScenarioNames) const;
};

// Ground-truth buffers come from one pinhole ray through each pixel centre, so labels are
// exact and do not depend on spp, jitter or the lens.
struct FrameBuffers {
  cv::Mat linear;    // CV_32FC3, RGB, linear radiance before post-processing
  cv::Mat rgb;       // CV_8UC3, RGB, sRGB after post-processing
  cv::Mat depth;     // CV_32F, metres along the camera's view axis (z-depth); 0 = no hit
  cv::Mat normals;   // CV_32FC3, unit shading normal in camera space, facing the camera; 0 = no hit
  cv::Mat instance;  // CV_16U, Instance::instance_id; 0 = background
  cv::Mat semantic;  // CV_16U, Instance::semantic_id; 0 = background
  // CV_32FC2, how far the surface seen moves across the image while the shutter is open
  // (pixels, x right and y down; Mesh::motion projected); empty when nothing in the scene moves.
  cv::Mat motion;
};

// Wall-clock milliseconds per phase of the last render (trace and shade are CPU time summed
// over threads, scaled to the wall time of the tracing loop).
struct RenderTimings {
  double trace_ms = 0;    // primary rays
  double shade_ms = 0;    // shading incl. shadow and environment rays
  double edges_ms = 0;    // adaptive anti-aliasing: finding the pixels to refine
  double denoise_ms = 0;  // lighting smoothing and compositing
  double post_ms = 0;
  double refined_fraction = 1;  // of pixels that took every sample (adaptive anti-aliasing)
  long long rays = 0;           // all rays traced (primary + shadow + environment + ground truth)
};

struct RayQuery {
  bool hit = false;
  float distance = 0;  // from the ray origin to the first hit (metres)
  Eigen::Vector3f position = Eigen::Vector3f::Zero();
  std::uint16_t instance_id = 0;
  std::uint16_t semantic_id = 0;
  int instance_index = -1;  // index into Scene::instances
};

class Renderer {
 public:
  // Builds the Embree scene and decodes textures. Throws Error for unreadable images.
  explicit Renderer(const scene::Scene& scene);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  FrameBuffers render(const RenderOptions& options = {});

  // Renders from another camera from now on: the ray-tracing structure and the textures do not
  // depend on the camera, so nothing is rebuilt (generate's framing moves the camera this way).
  void set_camera(const scene::Camera& camera) { scene_.camera = camera; }

  // First surface along the ray from the camera toward `point` (no distance limit). The point
  // is visible when the hit distance is at least ‖point − camera‖ minus a tolerance.
  RayQuery first_hit_toward(const Eigen::Vector3f& point) const;
  // First surface along origin + t·direction, t in (0, max_distance].
  RayQuery cast(const Eigen::Vector3f& origin, const Eigen::Vector3f& direction,
                float max_distance = 1e30f) const;

  double build_ms() const { return build_ms_; }
  const RenderTimings& timings() const { return timings_; }
  const scene::Scene& scene() const { return scene_; }

  struct Geometry;       // per-instance shading data (private to renderer.cpp)
  struct PixelLighting;  // per-frame decoupled-shading buffers (private to renderer.cpp)
  class TileIntegrator;  // one tile's samples, step by step (private to renderer.cpp)

 private:
  // Samples [sample_begin, sample_end) of one 8×8 tile. sample_begin = 0 starts every pixel;
  // later passes continue only the pixels whose `refine` entry is set.
  void render_tile(int tile_x, int tile_y, int sample_begin, int sample_end,
                   const std::uint8_t* refine, const RenderOptions& options, FrameBuffers& out,
                   PixelLighting& lighting, double& trace_ns, double& shade_ns,
                   long long& rays) const;
  Eigen::Vector3f background(float px, float py, const Eigen::Vector3f& dir) const;
  Eigen::Vector3f environment(const Eigen::Vector3f& dir) const;  // bilinear: what the camera sees
  // The radiance lighting uses: nearest cell of the sampling grid, so it matches the sampling
  // pdf exactly (a bilinear lookup next to a 34 000-bright sun pixel made fireflies).
  Eigen::Vector3f environment_lighting(const Eigen::Vector3f& dir) const;
  // Importance sampling of an environment map by luminance × sin θ on a coarse grid: a
  // direction and its solid-angle pdf from two uniform numbers.
  void build_environment_sampling();
  Eigen::Vector3f sample_environment(float r1, float r2, float& pdf) const;
  float environment_pdf(const Eigen::Vector3f& dir) const;  // of sample_environment

  scene::Scene scene_;
  RTCDevice device_ = nullptr;
  RTCScene rtc_scene_ = nullptr;
  std::vector<Geometry> geometries_;
  std::vector<TextureSampler> material_textures_;
  std::vector<Eigen::Matrix3f> hue_rotations_;  // per material, of its hue offset
  TextureSampler background_texture_;
  cv::Mat background_image_;
  cv::Mat environment_map_;
  cv::Mat environment_lighting_map_;  // the map at the sampling grid's resolution
  int env_grid_w_ = 0, env_grid_h_ = 0;
  std::vector<float> env_row_cdf_;   // env_grid_h_ + 1 entries, normalised
  std::vector<float> env_cell_cdf_;  // per row, env_grid_w_ + 1 entries, normalised
  std::vector<int> lights_on_;       // indices of point lights that are on
  std::vector<float> light_cdf_;     // power-proportional selection
  std::vector<float> light_power_;   // per light that is on
  // Up to this many lights are selected per shading point by their contribution there.
  static constexpr int kLocalLights = 16;
  double build_ms_ = 0;
  RenderTimings timings_;
};

}  // namespace wheelpose::render
