#pragma once
// What renderer.cpp and tile_integrator.cpp share, private to the render layer: the per-instance
// shading data, the per-frame decoupled-shading buffers, ray helpers and the tile integrator.

#include <embree3/rtcore.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <optional>
#include <vector>

#include "core/random.h"
#include "render/denoise.h"
#include "render/packet_mask.h"
#include "render/renderer.h"
#include "render/strata.h"

namespace wheelpose::render {

using Clock = std::chrono::steady_clock;
inline constexpr float kPi = std::numbers::pi_v<float>;
inline constexpr int kTile = 8;
inline constexpr float kInf = std::numeric_limits<float>::infinity();

struct Renderer::Geometry {
  bool present = false;
  const float* vertices = nullptr;       // world space, 3 floats each (Embree's vertex buffer)
  std::vector<Eigen::Vector3f> normals;  // world space; empty → geometric normal
  std::vector<Eigen::Vector2f> uvs;
  std::vector<Eigen::Vector3i> triangles;
  std::vector<Eigen::Vector3f> motion;  // world space, over the open shutter; empty → still
  int material = 0;
  float strands_per_uv = 0.0f, strand_coverage = 1.0f;  // alpha cards (render/strands.h)
  std::uint16_t instance_id = 0;
  std::uint16_t semantic_id = 0;
};

// Per-frame buffers of decoupled shading: each pixel's lighting (from its light samples, kept
// apart from surface colour so it can be denoised) and what the other samples need from it.
// Row-major, one entry per pixel.
struct Renderer::PixelLighting {
  struct Reuse {
    float albedo_sum[3] = {0, 0, 0};  // over the samples that reuse the pixel's lighting
    float count = 0;                  // how many samples reuse it
    float samples = 0;                // how many samples the pixel took
    float own[3] = {0, 0, 0};         // radiance summed over samples lit on their own
    // The sun's part of the pixel's lighting, not smoothed: a ray toward a 0.5° disc is nearly
    // noise-free, so sun shadows stay sharp (tracing it for every sample instead costs 25 %).
    PixelLight sun;
  };
  GuidePlanes guide;              // surface, normal and position of sample 0
  std::vector<PixelLight> light;  // point lights and sky, mean over the pixel's light samples
  // One diffuse bounce (RenderOptions::bounce), kept apart so it can be smoothed over a wider
  // window: it varies slowly over a surface, and one bounce ray per pixel is noisy.
  std::vector<PixelLight> bounce;
  std::vector<Reuse> reuse;
  DenoiseScratch denoise_scratch;
  // Per pixel, where its stream stood after pass 1: later passes continue from there.
  std::vector<std::uint64_t> stream_positions;
  std::vector<float> first_color[3];  // mean albedo or background of pass 1, a plane per channel
  std::vector<std::uint8_t> refine;   // pixels that take the remaining samples
};

// Orthonormal basis with the unit vector w as its third axis, without a square root or a
// normalisation (Duff et al. 2017, "Building an Orthonormal Basis, Revisited").
inline void basis(const Eigen::Vector3f& w, Eigen::Vector3f& u, Eigen::Vector3f& v) {
  const float sign = std::copysign(1.0f, w.z());
  const float a = -1.0f / (sign + w.z());
  const float b = w.x() * w.y() * a;
  u = Eigen::Vector3f(1.0f + sign * w.x() * w.x() * a, sign * b, -sign * w.x());
  v = Eigen::Vector3f(b, sign + w.y() * w.y() * a, -w.y());
}

// A cosine-weighted direction about the unit vector n from two uniform numbers in [0, 1): a
// uniform point of the unit disk lifted onto the hemisphere (Malley's method); unit by
// construction.
inline Eigen::Vector3f cosine_direction(const Eigen::Vector3f& n, float r1, float r2) {
  Eigen::Vector3f u, v;
  basis(n, u, v);
  const float radius = std::sqrt(r1), angle = 2 * kPi * r2;
  return radius * std::cos(angle) * u + radius * std::sin(angle) * v +
         std::sqrt(std::max(0.0f, 1 - r1)) * n;
}

inline void set_ray(RTCRay8& r, int k, const Eigen::Vector3f& o, const Eigen::Vector3f& d,
                    float tfar) {
  r.org_x[k] = o.x();
  r.org_y[k] = o.y();
  r.org_z[k] = o.z();
  r.dir_x[k] = d.x();
  r.dir_y[k] = d.y();
  r.dir_z[k] = d.z();
  r.tnear[k] = 0.0f;
  r.tfar[k] = tfar;
  r.time[k] = 0.0f;
  r.mask[k] = 0xFFFFFFFFu;
  r.id[k] = static_cast<unsigned>(k);
  r.flags[k] = 0;
}

// Width of one pixel in uv units at a hit on triangle `tri`: the pixel's width in metres at
// `distance` (`pixel_angle` radians), widened by the slant as the geometric mean of the two
// axes, times the triangle's uv units per metre. 0 when the triangle has no uv extent.
inline float uv_footprint(const Renderer::Geometry& g, const Eigen::Vector3i& tri, float distance,
                          float cos_view, float pixel_angle) {
  auto p = [&](int i) { return Eigen::Map<const Eigen::Vector3f>(g.vertices + 3 * i); };
  const float area_world = (p(tri[1]) - p(tri[0])).cross(p(tri[2]) - p(tri[0])).norm();
  const Eigen::Vector2f a = g.uvs[tri[1]] - g.uvs[tri[0]], b = g.uvs[tri[2]] - g.uvs[tri[0]];
  const float area_uv = std::abs(a.x() * b.y() - a.y() * b.x());
  if (area_world <= 0.0f || area_uv <= 0.0f) return 0.0f;
  const float metres = distance * pixel_angle / std::sqrt(std::max(std::abs(cos_view), 0.05f));
  return metres * std::sqrt(area_uv / area_world);
}

// Everything phase 2 (shading) needs about one primary ray.
struct PrimarySample {
  Eigen::Vector3f origin, dir;
  float px = 0, py = 0;  // film position (pixels) for the background
};

// One 8×8 tile's samples [sample_begin, sample_end), in the steps of a pass: pick the pixels,
// start their random streams, then per sample: camera rays → primary hits (→ ground truth at
// sample 0) → per 4×2 packet: surfaces, one shadow ray per light kind (sun, a point light, the
// sky) → accumulate; finally store what later passes and the denoiser need.
class Renderer::TileIntegrator {
 public:
  TileIntegrator(const Renderer& renderer, int tile_x, int tile_y, int sample_begin, int sample_end,
                 const RenderOptions& options, double& trace_ns, double& shade_ns,
                 long long& ray_count);

  void run(const std::uint8_t* refine, FrameBuffers& out, PixelLighting& lighting);

 private:
  static constexpr int kPixels = kTile * kTile;
  static constexpr int kPackets = kPixels / 8;  // 4×2-pixel packets per tile
  // A sample reuses its pixel's lighting when it lands on the same surface as sample 0 with a
  // normal within ≈ 18°; otherwise (silhouettes, creases) it is lit on its own.
  static constexpr float kReuseNormalCos = 0.95f;

  // Where a primary ray landed and what the surface looks like there.
  struct SurfacePoint {
    int surface;
    Eigen::Vector3f position, geometric_normal, normal, albedo;
    const scene::Material* material;
  };
  // One packet's shadow rays: 0 = sun, 1 = one point light, 2 = environment; per ray the light
  // × cos split into the part the albedo scales and the specular part.
  struct ShadowRays {
    alignas(32) std::array<RTCRay8, 3> rays;
    std::array<PacketMask, 3> valid{};
    std::array<std::array<Eigen::Vector3f, 8>, 3> to_diffuse, to_specular;
    std::array<bool, 8> into_pixel{};  // lighting goes to the pixel (true) or the sample only
    std::array<Eigen::Vector3f, 8> albedos;
  };

  bool take_pixels(const std::uint8_t* refine);
  void start_streams(const PixelLighting& lighting);
  void pixel_of(int lane, int& x, int& y) const {
    x = tile_x_ * kTile + slot_[lane] % kTile;
    y = tile_y_ * kTile + slot_[lane] / kTile;
  }
  std::size_t index_of(int x, int y) const { return static_cast<std::size_t>(y) * w_ + x; }
  void camera_ray(float fx, float fy, float lu, float lv, Eigen::Vector3f& o,
                  Eigen::Vector3f& d) const;
  void pinhole_rays();
  void sample_rays(int s);
  void trace_primary();
  void store_ground_truth(FrameBuffers& out) const;
  // FrameBuffers::motion of the point `offset` from the camera on triangle `prim` of `g`.
  Eigen::Vector2f image_motion(const Geometry& g, unsigned prim, float u, float v,
                               const Eigen::Vector3f& offset) const;
  void shade_packet(int p, int s);
  SurfacePoint surface_at(int p, int k) const;
  // The surface lane k of `rh` hit, for a ray from `origin` along `dir`; `pixel_angle` sizes
  // the texture filter (0: a point sample).
  SurfacePoint surface_of(const RTCRayHit8& rh, int k, const Eigen::Vector3f& origin,
                          const Eigen::Vector3f& dir, float pixel_angle) const;
  // RenderOptions::bounce: one cosine-weighted ray from each lit sample of packet p; where it
  // hits a surface, that surface's light from the sun and one point light, scaled by its albedo,
  // is light arriving at the sample (an unbiased one-bounce estimate; the sky's bounce is left
  // out). `primary` says where each lane's light goes, as for its direct light.
  void add_bounce(int p, RTCRayHit8& rays, PacketMask valid, const ShadowRays& primary);
  // At a bounce's surface a lamp's 1/d² is floored at this distance: bounce rays that land
  // beside a ceiling lamp would otherwise carry hundreds of times the light of the others and
  // speckle the whole room (fireflies the denoiser cannot take). The light lost is what that
  // close patch of wall or ceiling adds beyond the same patch a metre away.
  static constexpr float kBounceMinLightDistance = 1.0f;
  void sample_lights(int p, int k, int s, const SurfacePoint& at, ShadowRays& shadows);
  void add_light(ShadowRays& shadows, int q, int k, const Eigen::Vector3f& l, float cos_l,
                 const Eigen::Vector3f& radiance, const SurfacePoint& at,
                 const Eigen::Vector3f& view) const;
  // `u`: the two random numbers of the light's sample (stratified for primary surfaces).
  void sample_sun(int k, std::array<float, 2> u, const Eigen::Vector3f& origin,
                  const SurfacePoint& at, const Eigen::Vector3f& view, ShadowRays& shadows) const;
  // `min_distance_squared` floors d² in the light's 1/d² (m²).
  void sample_point_light(int k, std::array<float, 2> u, RandomStream& rng,
                          const Eigen::Vector3f& origin, const SurfacePoint& at,
                          const Eigen::Vector3f& view, ShadowRays& shadows,
                          float min_distance_squared) const;
  void sample_environment(int k, int px, int py, RandomStream& rng, const Eigen::Vector3f& origin,
                          const SurfacePoint& at, ShadowRays& shadows) const;
  void resolve_shadows(int p, ShadowRays& shadows);
  void store_lighting(PixelLighting& lighting) const;

  const Renderer& r_;
  const RenderOptions& options_;
  const int tile_x_, tile_y_, sample_begin_, sample_end_;
  double& trace_ns_;
  double& shade_ns_;
  long long& ray_count_;
  // The camera.
  const scene::Camera& cam_;
  const int w_, h_;
  const float tan_half_, aspect_;
  const Eigen::Matrix3f rot_;
  const Eigen::Vector3f forward_;
  const bool lens_;
  const float pixel_angle_;  // radians per pixel
  // The sun (off below the horizon at night) and the sky.
  const Eigen::Vector3f sun_dir_;
  const bool sun_on_;
  const float sun_cos_max_;
  Eigen::Vector3f sun_u_, sun_v_;
  const bool env_on_;
  // The sun cone, the light choice and the sky direction are stratified across pixels. A tile
  // lies inside one strata block, so one block serves every pixel of it; made when a pixel
  // first samples the lights in a sample (in later passes few do).
  const ScreenStrata strata_;
  std::optional<ScreenStrata::Block> strata_block_;
  RTCIntersectContext coherent_, incoherent_;

  std::array<RTCRayHit8, kPackets> hits_;
  std::array<PacketMask, kPackets> valid_;
  std::array<PrimarySample, kPixels> prim_;
  // Per pixel: radiance of samples lit on their own, and the pixel's lighting (see
  // PixelLighting) accumulated over its light samples.
  std::array<Eigen::Vector3f, kPixels> own_, diffuse_, specular_, sun_diffuse_, sun_specular_,
      bounce_, albedo_sum_, normal0_, position0_;
  std::array<int, kPixels> surface0_, light_count_, reuse_count_;
  // The pixels this pass takes, packed into the first lanes (slot = offset in the tile).
  std::array<std::uint8_t, kPixels> slot_{};
  int active_ = 0;
  // One stream per pixel, drawn from in sample order (and continued by later passes): what a
  // pixel draws depends only on its own hits, so the image does not depend on tiles or threads.
  std::array<std::optional<RandomStream>, kPixels> streams_;
};

}  // namespace wheelpose::render
