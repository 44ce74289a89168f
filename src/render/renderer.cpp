#include "render/renderer.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <sstream>
#include <string>

#include "core/error.h"
#include "core/random.h"
#include "render/adaptive.h"
#include "render/embree_device.h"
#include "render/packet_mask.h"
#include "render/post.h"
#include "render/strata.h"

namespace wheelpose::render {

struct Renderer::Geometry {
  bool present = false;
  const float* vertices = nullptr;       // world space, 3 floats each (Embree's vertex buffer)
  std::vector<Eigen::Vector3f> normals;  // world space; empty → geometric normal
  std::vector<Eigen::Vector2f> uvs;
  std::vector<Eigen::Vector3i> triangles;
  int material = 0;
  std::uint16_t instance_id = 0;
  std::uint16_t semantic_id = 0;
};

namespace {

using Clock = std::chrono::steady_clock;
constexpr float kPi = std::numbers::pi_v<float>;
constexpr int kTile = 8;
constexpr float kInf = std::numeric_limits<float>::infinity();

double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// Orthonormal basis with the unit vector w as its third axis, without a square root or a
// normalisation (Duff et al. 2017, "Building an Orthonormal Basis, Revisited").
void basis(const Eigen::Vector3f& w, Eigen::Vector3f& u, Eigen::Vector3f& v) {
  const float sign = std::copysign(1.0f, w.z());
  const float a = -1.0f / (sign + w.z());
  const float b = w.x() * w.y() * a;
  u = Eigen::Vector3f(1.0f + sign * w.x() * w.x() * a, sign * b, -sign * w.x());
  v = Eigen::Vector3f(b, sign + w.y() * w.y() * a, -w.y());
}

void set_ray(RTCRay8& r, int k, const Eigen::Vector3f& o, const Eigen::Vector3f& d, float tfar) {
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

// Reusable heap objects for concurrent callers: acquire() hands out a released one when there is
// one, else a new one; at most as many exist as renders ever ran at once.
template <typename T>
class BufferPool {
 public:
  std::unique_ptr<T> acquire() {
    std::lock_guard lock(mutex_);
    if (free_.empty()) return std::make_unique<T>();
    std::unique_ptr<T> item = std::move(free_.back());
    free_.pop_back();
    return item;
  }
  void release(std::unique_ptr<T> item) {
    std::lock_guard lock(mutex_);
    free_.push_back(std::move(item));
  }

 private:
  std::mutex mutex_;
  std::vector<std::unique_ptr<T>> free_;
};

// Width of one pixel in uv units at a hit on triangle `tri`: the pixel's width in metres at
// `distance` (`pixel_angle` radians), widened by the slant as the geometric mean of the two
// axes, times the triangle's uv units per metre. 0 when the triangle has no uv extent.
float uv_footprint(const Renderer::Geometry& g, const Eigen::Vector3i& tri, float distance,
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

}  // namespace

Renderer::Renderer(const scene::Scene& scene) : scene_(scene) {
  const auto start = Clock::now();
  // Textures first: a bad image fails before any Embree work.
  for (std::size_t i = 0; i < scene_.materials.size(); ++i) {
    hue_rotations_.push_back(hue_rotation(scene_.materials[i].hue_offset_deg));
    const auto& t = scene_.materials[i].texture;
    material_textures_.emplace_back(t, scene::resolve_path(scene_, t.path),
                                    "/materials/" + std::to_string(i) + "/texture/path");
  }
  background_texture_ = TextureSampler(scene_.background.texture,
                                       scene::resolve_path(scene_, scene_.background.texture.path),
                                       "/background/texture/path");
  if (!scene_.background.image.empty()) {
    background_image_ = load_linear_image(scene::resolve_path(scene_, scene_.background.image),
                                          "/background/image");
  }
  if (scene_.environment && !scene_.environment->path.empty()) {
    environment_map_ = load_linear_image(scene::resolve_path(scene_, scene_.environment->path),
                                         "/environment/path");
    build_environment_sampling();
  }
  float total = 0;
  for (std::size_t i = 0; i < scene_.point_lights.size(); ++i) {
    const auto& l = scene_.point_lights[i];
    const float power = l.intensity * l.color.sum() / 3.0f;
    if (!l.on || power <= 0) continue;
    lights_on_.push_back(static_cast<int>(i));
    light_power_.push_back(power);
    total += power;
    light_cdf_.push_back(total);
  }
  for (float& c : light_cdf_) c /= total;

  device_ = shared_embree_device();
  rtcRetainDevice(device_);
  rtc_scene_ = rtcNewScene(device_);
  rtcSetSceneBuildQuality(rtc_scene_, RTC_BUILD_QUALITY_LOW);
  geometries_.resize(scene_.instances.size());
  for (std::size_t i = 0; i < scene_.instances.size(); ++i) {
    const auto& in = scene_.instances[i];
    WHEELPOSE_CHECK(in.mesh >= 0 && in.mesh < static_cast<int>(scene_.meshes.size()));
    WHEELPOSE_CHECK(in.material >= 0 && in.material < static_cast<int>(scene_.materials.size()));
    const auto& mesh = scene_.meshes[in.mesh];
    if (mesh.triangles.empty()) continue;
    Geometry& g = geometries_[i];
    g.present = true;
    g.material = in.material;
    g.instance_id = in.instance_id;
    g.semantic_id = in.semantic_id;
    g.triangles = mesh.triangles;
    g.uvs = mesh.uvs;
    const Eigen::Affine3f xf(in.transform);
    const Eigen::Matrix3f normal_matrix = xf.linear().inverse().transpose();
    RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    // A LOW scene is two-level and builds each geometry at the geometry's own quality (default
    // MEDIUM): LOW here made commits 3× faster for 3 % less CPU per generated frame overall.
    rtcSetGeometryBuildQuality(geom, RTC_BUILD_QUALITY_LOW);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0,
                                                          RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                                          mesh.positions.size()));
    g.vertices = v;
    for (std::size_t k = 0; k < mesh.positions.size(); ++k) {
      const Eigen::Vector3f p = xf * mesh.positions[k];
      v[3 * k] = p.x();
      v[3 * k + 1] = p.y();
      v[3 * k + 2] = p.z();
    }
    auto* idx = static_cast<unsigned*>(
        rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                3 * sizeof(unsigned), mesh.triangles.size()));
    for (std::size_t k = 0; k < mesh.triangles.size(); ++k) {
      for (int c = 0; c < 3; ++c) idx[3 * k + c] = static_cast<unsigned>(mesh.triangles[k][c]);
    }
    g.normals.reserve(mesh.normals.size());
    for (const auto& n : mesh.normals) g.normals.push_back((normal_matrix * n).normalized());
    rtcCommitGeometry(geom);
    rtcAttachGeometryByID(rtc_scene_, geom, static_cast<unsigned>(i));
    rtcReleaseGeometry(geom);
  }
  rtcCommitScene(rtc_scene_);
  throw_on_embree_error("building the scene");
  build_ms_ = ms_since(start);
}

Renderer::~Renderer() {
  if (rtc_scene_) rtcReleaseScene(rtc_scene_);
  if (device_) rtcReleaseDevice(device_);
}

Eigen::Vector3f Renderer::environment(const Eigen::Vector3f& d) const {
  const auto& e = *scene_.environment;
  if (environment_map_.empty()) return e.color * e.intensity;
  const float u = 0.5f + std::atan2(d.x(), -d.z()) / (2 * kPi) + e.rotation_deg / 360.0f;
  const float v = std::acos(std::clamp(d.y(), -1.0f, 1.0f)) / kPi;
  return sample_bilinear(environment_map_, u, std::min(v, 0.9999f)) * e.intensity;
}

Eigen::Vector3f Renderer::environment_lighting(const Eigen::Vector3f& d) const {
  const auto& e = *scene_.environment;
  const float u = 0.5f + std::atan2(d.x(), -d.z()) / (2 * kPi) + e.rotation_deg / 360.0f;
  const float theta = std::acos(std::clamp(d.y(), -1.0f, 1.0f));
  const int x = std::clamp(static_cast<int>((u - std::floor(u)) * env_grid_w_), 0, env_grid_w_ - 1);
  const int y = std::clamp(static_cast<int>(theta / kPi * env_grid_h_), 0, env_grid_h_ - 1);
  const cv::Vec3f c = environment_lighting_map_.at<cv::Vec3f>(y, x);
  return Eigen::Vector3f(c[0], c[1], c[2]) * e.intensity;
}

void Renderer::build_environment_sampling() {
  // The map's own resolution (up to 2048 × 1024): a coarser grid averages a bright sun pixel
  // (≈ 34 000 in Blender's maps, whose mean is ≈ 1) into its cell, so the pdf underestimates it
  // and the few rays that hit it become fireflies.
  env_grid_w_ = std::min(environment_map_.cols, 2048);
  env_grid_h_ = std::min(environment_map_.rows, 1024);
  cv::Mat& small = environment_lighting_map_;
  cv::resize(environment_map_, small, cv::Size(env_grid_w_, env_grid_h_), 0, 0, cv::INTER_AREA);
  env_row_cdf_.assign(static_cast<std::size_t>(env_grid_h_) + 1, 0.0f);
  env_cell_cdf_.assign(static_cast<std::size_t>(env_grid_h_) * (env_grid_w_ + 1), 0.0f);
  for (int y = 0; y < env_grid_h_; ++y) {
    const float sin_theta = std::sin(kPi * (static_cast<float>(y) + 0.5f) / env_grid_h_);
    float* row = &env_cell_cdf_[static_cast<std::size_t>(y) * (env_grid_w_ + 1)];
    for (int x = 0; x < env_grid_w_; ++x) {
      const cv::Vec3f c = small.at<cv::Vec3f>(y, x);
      const float lum = std::max(0.0f, 0.2126f * c[0] + 0.7152f * c[1] + 0.0722f * c[2]);
      row[x + 1] = row[x] + lum * sin_theta + 1e-6f;  // every direction keeps a chance
    }
    env_row_cdf_[static_cast<std::size_t>(y) + 1] = env_row_cdf_[y] + row[env_grid_w_];
    for (int x = 1; x <= env_grid_w_; ++x) row[x] /= row[env_grid_w_];
  }
  for (float& c : env_row_cdf_) c /= env_row_cdf_.back();
}

Eigen::Vector3f Renderer::sample_environment(float r1, float r2, float& pdf) const {
  auto pick = [](const float* cdf, int n, float r, float& frac) {
    const int i = std::clamp(
        static_cast<int>(std::upper_bound(cdf + 1, cdf + n + 1, r) - (cdf + 1)), 0, n - 1);
    const float width = cdf[i + 1] - cdf[i];
    frac = width > 0 ? std::clamp((r - cdf[i]) / width, 0.0f, 0.9999f) : 0.5f;
    return i;
  };
  float fy = 0, fx = 0;
  const int y = pick(env_row_cdf_.data(), env_grid_h_, r1, fy);
  const float* row = &env_cell_cdf_[static_cast<std::size_t>(y) * (env_grid_w_ + 1)];
  const int x = pick(row, env_grid_w_, r2, fx);
  const float cell_probability = (env_row_cdf_[y + 1] - env_row_cdf_[y]) * (row[x + 1] - row[x]);
  const float u = (static_cast<float>(x) + fx) / env_grid_w_;
  const float v = (static_cast<float>(y) + fy) / env_grid_h_;
  const float theta = kPi * v;
  // Inverse of environment(): u = 0.5 + atan2(d.x, −d.z) / 2π + rotation.
  const float phi = 2 * kPi * (u - 0.5f - scene_.environment->rotation_deg / 360.0f);
  const float sin_theta = std::sin(theta);
  pdf = sin_theta > 1e-6f
            ? cell_probability * env_grid_w_ * env_grid_h_ / (2 * kPi * kPi * sin_theta)
            : 0.0f;
  return Eigen::Vector3f(sin_theta * std::sin(phi), std::cos(theta), -sin_theta * std::cos(phi));
}

float Renderer::environment_pdf(const Eigen::Vector3f& d) const {
  const float u =
      0.5f + std::atan2(d.x(), -d.z()) / (2 * kPi) + scene_.environment->rotation_deg / 360.0f;
  const float theta = std::acos(std::clamp(d.y(), -1.0f, 1.0f));
  const float sin_theta = std::sin(theta);
  if (sin_theta <= 1e-6f) return 0.0f;
  const int x = std::clamp(static_cast<int>((u - std::floor(u)) * env_grid_w_), 0, env_grid_w_ - 1);
  const int y = std::clamp(static_cast<int>(theta / kPi * env_grid_h_), 0, env_grid_h_ - 1);
  const float* row = &env_cell_cdf_[static_cast<std::size_t>(y) * (env_grid_w_ + 1)];
  const float cell_probability = (env_row_cdf_[y + 1] - env_row_cdf_[y]) * (row[x + 1] - row[x]);
  return cell_probability * env_grid_w_ * env_grid_h_ / (2 * kPi * kPi * sin_theta);
}

Eigen::Vector3f Renderer::background(float px, float py, const Eigen::Vector3f& dir) const {
  const float w = static_cast<float>(scene_.camera.width);
  const float h = static_cast<float>(scene_.camera.height);
  if (!background_image_.empty()) {
    // Cover the frame keeping the image's aspect ratio (centre crop, never stretched).
    const float iw = static_cast<float>(background_image_.cols);
    const float ih = static_cast<float>(background_image_.rows);
    const float s = std::max(w / iw, h / ih);
    const float u = ((px - 0.5f * w) / s + 0.5f * iw) / iw;
    const float v = ((py - 0.5f * h) / s + 0.5f * ih) / ih;
    return sample_bilinear(background_image_, std::clamp(u, 0.0f, 0.9999f),
                           std::clamp(v, 0.0f, 0.9999f));
  }
  if (background_texture_.active()) {
    // Square cells in screen space; an image texture tiles and tints with the colour.
    const Eigen::Vector3f t = background_texture_.at(px / h, 1.0f - py / h, 1.0f / h);
    return scene_.background.texture.kind == scene::TextureKind::kImage
               ? Eigen::Vector3f(scene_.background.color.cwiseProduct(t))
               : t;
  }
  if (!environment_map_.empty()) return environment(dir);
  return scene_.background.color;
}

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
  std::vector<Reuse> reuse;
  DenoiseScratch denoise_scratch;
  // Per pixel, where its stream stood after pass 1: later passes continue from there.
  std::vector<std::uint64_t> stream_positions;
  std::vector<float> first_color[3];  // mean albedo or background of pass 1, a plane per channel
  std::vector<std::uint8_t> refine;   // pixels that take the remaining samples
};

void RenderOptions::check(const Names& names) const {
  auto outside = [](const char* name, double value, const std::string& range) {
    std::ostringstream text;
    text << name << " (" << value << ") must be between " << range;
    throw Error(text.str());
  };
  if (spp < 1 || spp > kMaxSpp) outside(names.spp, spp, "1 and " + std::to_string(kMaxSpp));
  if (light_samples < 1 || light_samples > spp) {
    outside(names.light_samples, light_samples,
            std::string("1 and ") + names.spp + " (" + std::to_string(spp) + ")");
  }
  if (denoise_radius < 0 || denoise_radius > kMaxDenoiseRadius)
    outside(names.denoise_radius, denoise_radius, "0 and " + std::to_string(kMaxDenoiseRadius));
  if (!(adaptive_contrast >= -1.0f && adaptive_contrast <= 1.0f))
    outside(names.adaptive_contrast, adaptive_contrast, "-1 and 1");
}

FrameBuffers Renderer::render(const RenderOptions& options) {
  const int w = scene_.camera.width, h = scene_.camera.height;
  options.check();
  FrameBuffers out;
  // Not cleared: pass 1 writes every pixel's ground truth and the composition every colour.
  out.linear = cv::Mat(h, w, CV_32FC3);
  out.depth = cv::Mat(h, w, CV_32F);
  out.normals = cv::Mat(h, w, CV_32FC3);
  out.instance = cv::Mat(h, w, CV_16U);
  out.semantic = cv::Mat(h, w, CV_16U);
  // The decoupled-shading buffers (≈ 140 MB at 1280×720) come from a pool shared by all
  // renderers: allocating them afresh each frame made the kernel fault in and zero every page.
  static BufferPool<PixelLighting> pool;
  std::unique_ptr<PixelLighting> pooled = pool.acquire();
  PixelLighting& lighting = *pooled;
  const std::size_t pixels = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  lighting.guide.resize(pixels);
  lighting.stream_positions.resize(pixels);
  lighting.light.resize(pixels);
  lighting.reuse.resize(pixels);
  for (auto& plane : lighting.first_color) plane.resize(pixels);
  const int tiles_x = (w + kTile - 1) / kTile, tiles_y = (h + kTile - 1) / kTile;
  std::atomic<long long> trace_ns{0}, shade_ns{0}, rays{0};
  auto run_pass = [&](int sample_begin, int sample_end, const std::uint8_t* refine) {
    tbb::parallel_for(tbb::blocked_range<int>(0, tiles_x * tiles_y),
                      [&](const tbb::blocked_range<int>& r) {
                        double t = 0, s = 0;
                        long long n = 0;
                        for (int i = r.begin(); i < r.end(); ++i) {
                          render_tile(i % tiles_x, i / tiles_x, sample_begin, sample_end, refine,
                                      options, out, lighting, t, s, n);
                        }
                        trace_ns += static_cast<long long>(t);
                        shade_ns += static_cast<long long>(s);
                        rays += n;
                      });
  };
  const auto start = Clock::now();
  // Adaptive: every pixel takes its light samples, then only edge pixels the rest.
  const bool adaptive = options.adaptive_contrast >= 0 && scene_.camera.aperture_radius <= 0 &&
                        options.light_samples < options.spp;
  run_pass(0, adaptive ? options.light_samples : options.spp, nullptr);
  // The guide is final after pass 1 (later passes keep sample 0's surface).
  timings_.refined_fraction = 1.0;
  timings_.edges_ms = 0;
  if (adaptive) {
    const auto edges_start = Clock::now();
    mark_edges(w, h, lighting.guide, lighting.first_color, options.adaptive_contrast,
               lighting.refine);
    // Slivers found per geometry in parallel, then drawn in geometry order.
    const scene::Projector projector(scene_.camera);
    std::vector<std::vector<Sliver>> slivers(geometries_.size());
    tbb::parallel_for(std::size_t{0}, geometries_.size(), [&](std::size_t i) {
      const Geometry& g = geometries_[i];
      if (g.present) find_slivers(projector, g.vertices, g.triangles, slivers[i]);
    });
    for (const auto& found : slivers) mark_slivers(found, w, h, lighting.refine);
    const auto marked = std::count(lighting.refine.begin(), lighting.refine.end(), 1);
    timings_.refined_fraction = static_cast<double>(marked) / static_cast<double>(pixels);
    timings_.edges_ms = ms_since(edges_start);
    run_pass(options.light_samples, options.spp, lighting.refine.data());
  }
  // Trace and shade share the passes' wall time in proportion to their busy time.
  const double wall = ms_since(start) - timings_.edges_ms;
  const double busy = std::max(1.0, static_cast<double>(trace_ns + shade_ns));
  timings_.trace_ms = wall * static_cast<double>(trace_ns) / busy;
  timings_.shade_ms = wall * static_cast<double>(shade_ns) / busy;
  timings_.rays = rays;
  throw_on_embree_error("tracing rays");

  const auto denoise_start = Clock::now();
  if (options.denoise_radius > 0) {
    denoise_lighting(w, h, lighting.guide, options.denoise_radius, lighting.light,
                     lighting.denoise_scratch);
  }
  // Radiance = (Σ albedo of the reusing samples ⊙ lighting + their specular + samples lit on
  // their own) / samples taken.
  tbb::parallel_for(tbb::blocked_range<int>(0, h), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y < rows.end(); ++y) {
      auto* row = out.linear.ptr<cv::Vec3f>(y);
      for (int x = 0; x < w; ++x) {
        const std::size_t i = static_cast<std::size_t>(y) * w + x;
        const PixelLight& l = lighting.light[i];
        const PixelLighting::Reuse& r = lighting.reuse[i];
        const float inv = 1.0f / r.samples;
        for (int k = 0; k < 3; ++k) {
          row[x][k] = (r.albedo_sum[k] * (l.diffuse[k] + r.sun.diffuse[k]) +
                       r.count * (l.specular[k] + r.sun.specular[k]) + r.own[k]) *
                      inv;
        }
      }
    }
  });
  timings_.denoise_ms = ms_since(denoise_start);
  pool.release(std::move(pooled));

  const auto post_start = Clock::now();
  out.rgb = options.post ? apply_post(out.linear, out.depth, scene_.post,
                                      scene_.camera.focus_distance, scene_.seed)
                         : encode_srgb(out.linear);
  timings_.post_ms = ms_since(post_start);
  return out;
}

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
  void shade_packet(int p, int s);
  SurfacePoint surface_at(int p, int k) const;
  void sample_lights(int p, int k, int s, const SurfacePoint& at, ShadowRays& shadows);
  void add_light(ShadowRays& shadows, int q, int k, const Eigen::Vector3f& l, float cos_l,
                 const Eigen::Vector3f& radiance, const SurfacePoint& at,
                 const Eigen::Vector3f& view) const;
  void sample_sun(int k, int px, int py, const Eigen::Vector3f& origin, const SurfacePoint& at,
                  const Eigen::Vector3f& view, ShadowRays& shadows) const;
  void sample_point_light(int k, int px, int py, RandomStream& rng, const Eigen::Vector3f& origin,
                          const SurfacePoint& at, const Eigen::Vector3f& view,
                          ShadowRays& shadows) const;
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
      albedo_sum_, normal0_, position0_;
  std::array<int, kPixels> surface0_, light_count_, reuse_count_;
  // The pixels this pass takes, packed into the first lanes (slot = offset in the tile).
  std::array<std::uint8_t, kPixels> slot_{};
  int active_ = 0;
  // One stream per pixel, drawn from in sample order (and continued by later passes): what a
  // pixel draws depends only on its own hits, so the image does not depend on tiles or threads.
  std::array<std::optional<RandomStream>, kPixels> streams_;
};

Renderer::TileIntegrator::TileIntegrator(const Renderer& renderer, int tile_x, int tile_y,
                                         int sample_begin, int sample_end,
                                         const RenderOptions& options, double& trace_ns,
                                         double& shade_ns, long long& ray_count)
    : r_(renderer),
      options_(options),
      tile_x_(tile_x),
      tile_y_(tile_y),
      sample_begin_(sample_begin),
      sample_end_(sample_end),
      trace_ns_(trace_ns),
      shade_ns_(shade_ns),
      ray_count_(ray_count),
      cam_(renderer.scene_.camera),
      w_(cam_.width),
      h_(cam_.height),
      tan_half_(std::tan(0.5f * cam_.effective_vfov())),
      aspect_(static_cast<float>(w_) / static_cast<float>(h_)),
      rot_(cam_.orientation.normalized().toRotationMatrix()),
      forward_(rot_ * Eigen::Vector3f(0, 0, -1)),
      lens_(cam_.aperture_radius > 0.0f),
      pixel_angle_(2.0f * tan_half_ / static_cast<float>(h_)),
      sun_dir_(scene::sun_direction(renderer.scene_.sun)),
      sun_on_(renderer.scene_.sun.enabled && renderer.scene_.sun.intensity > 0 &&
              !(renderer.scene_.sun.solar && sun_dir_.y() <= 0.0f)),
      sun_cos_max_(std::cos(renderer.scene_.sun.angular_radius_deg * kPi / 180.0f)),
      env_on_(renderer.scene_.environment.has_value()),
      strata_(renderer.scene_.seed) {
  basis(sun_dir_, sun_u_, sun_v_);
  own_.fill(Eigen::Vector3f::Zero());
  diffuse_.fill(Eigen::Vector3f::Zero());
  specular_.fill(Eigen::Vector3f::Zero());
  sun_diffuse_.fill(Eigen::Vector3f::Zero());
  sun_specular_.fill(Eigen::Vector3f::Zero());
  albedo_sum_.fill(Eigen::Vector3f::Zero());
  normal0_.fill(Eigen::Vector3f::Zero());
  position0_.fill(Eigen::Vector3f::Zero());
  surface0_.fill(-1);
  light_count_.fill(0);
  reuse_count_.fill(0);
  rtcInitIntersectContext(&coherent_);
  coherent_.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  rtcInitIntersectContext(&incoherent_);
}

void Renderer::TileIntegrator::run(const std::uint8_t* refine, FrameBuffers& out,
                                   PixelLighting& lighting) {
  if (!take_pixels(refine)) return;
  start_streams(lighting);
  if (lens_ && sample_begin_ == 0) {
    pinhole_rays();
    trace_primary();
    ray_count_ += active_;
    store_ground_truth(out);
  }
  for (int s = sample_begin_; s < sample_end_; ++s) {
    const auto rays_start = Clock::now();
    static_assert(ScreenStrata::kBlock % kTile == 0);
    strata_block_.reset();
    sample_rays(s);
    shade_ns_ += std::chrono::duration<double, std::nano>(Clock::now() - rays_start).count();
    trace_primary();
    ray_count_ += active_;
    const auto shade_start = Clock::now();
    if (s == 0 && !lens_) store_ground_truth(out);
    for (int p = 0; p < kPackets; ++p) shade_packet(p, s);
    shade_ns_ += std::chrono::duration<double, std::nano>(Clock::now() - shade_start).count();
  }
  store_lighting(lighting);
}

// The pixels this pass takes, in 4×2 blocks' order: a later pass refines a few scattered
// pixels, and tracing them in full packets instead of the sparse 4×2 blocks they fall in takes
// a fraction of the packets. False when there are none.
bool Renderer::TileIntegrator::take_pixels(const std::uint8_t* refine) {
  for (int block = 0; block < kPixels; ++block) {
    const int p = block / 8, k = block % 8;
    const int local = ((p / 2) * 2 + k / 4) * kTile + (p % 2) * 4 + k % 4;
    const int x = tile_x_ * kTile + local % kTile, y = tile_y_ * kTile + local / kTile;
    if (x < w_ && y < h_ && (!refine || refine[index_of(x, y)]))
      slot_[active_++] = static_cast<std::uint8_t>(local);
  }
  if (active_ == 0) return false;
  for (int li = 0; li < kPixels; ++li) valid_[li / 8][li % 8] = li < active_ ? -1 : 0;
  for (RTCRayHit8& packet : hits_) switch_off_lanes(packet.ray);
  return true;
}

// Each pixel's stream; a later pass carries on from what the earlier samples left.
void Renderer::TileIntegrator::start_streams(const PixelLighting& lighting) {
  const StreamKey pixel_key("pixel");
  for (int li = 0; li < active_; ++li) {
    int x, y;
    pixel_of(li, x, y);
    const std::size_t i = index_of(x, y);
    RandomStream& stream =
        streams_[li].emplace(r_.scene_.seed, std::initializer_list<StreamKey>{pixel_key, i});
    if (sample_begin_ == 0) continue;
    stream.seek(lighting.stream_positions[i]);
    const PixelLighting::Reuse& r = lighting.reuse[i];
    const GuidePlanes& g = lighting.guide;
    own_[li] = Eigen::Vector3f(r.own[0], r.own[1], r.own[2]);
    albedo_sum_[li] = Eigen::Vector3f(r.albedo_sum[0], r.albedo_sum[1], r.albedo_sum[2]);
    reuse_count_[li] = static_cast<int>(r.count);
    surface0_[li] = g.surface[i];
    normal0_[li] = Eigen::Vector3f(g.geometry[0][i], g.geometry[1][i], g.geometry[2][i]);
  }
}

// Camera ray through film position (fx, fy) in pixels and lens sample (lu, lv) in [0, 1)².
void Renderer::TileIntegrator::camera_ray(float fx, float fy, float lu, float lv,
                                          Eigen::Vector3f& o, Eigen::Vector3f& d) const {
  const Eigen::Vector3f dc((2.0f * fx / w_ - 1.0f) * tan_half_ * aspect_,
                           (1.0f - 2.0f * fy / h_) * tan_half_, -1.0f);
  if (!lens_) {
    o = cam_.position;
    d = (rot_ * dc).normalized();
    return;
  }
  const float r = cam_.aperture_radius * std::sqrt(lu), phi = 2 * kPi * lv;
  const Eigen::Vector3f lens_point(r * std::cos(phi), r * std::sin(phi), 0.0f);
  const Eigen::Vector3f focus = dc * cam_.focus_distance;  // dc.z = −1: on the focal plane
  o = cam_.position + rot_ * lens_point;
  d = (rot_ * (focus - lens_point)).normalized();
}

// Pixel-centre pinhole rays, for the ground truth of a camera with a lens.
void Renderer::TileIntegrator::pinhole_rays() {
  for (int p = 0; p < kPackets; ++p) {
    for (int k = 0; k < 8; ++k) {
      int x, y;
      pixel_of(p * 8 + k, x, y);
      const Eigen::Vector3f dc((2.0f * (x + 0.5f) / w_ - 1.0f) * tan_half_ * aspect_,
                               (1.0f - 2.0f * (y + 0.5f) / h_) * tan_half_, -1.0f);
      set_ray(hits_[p].ray, k, cam_.position, (rot_ * dc).normalized(), kInf);
      hits_[p].hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
    }
  }
}

// Sample s's camera rays: sample 0 through the pixel centre, later ones jittered over the pixel.
void Renderer::TileIntegrator::sample_rays(int s) {
  for (int p = 0; p < kPackets; ++p) {
    for (int k = 0; k < 8; ++k) {
      if (!valid_[p][k]) continue;
      int x, y;
      pixel_of(p * 8 + k, x, y);
      RandomStream& rng = *streams_[p * 8 + k];
      const float jx = s == 0 ? 0.5f : static_cast<float>(rng.uniform01());
      const float jy = s == 0 ? 0.5f : static_cast<float>(rng.uniform01());
      const float lu = lens_ ? static_cast<float>(rng.uniform01()) : 0.0f;
      const float lv = lens_ ? static_cast<float>(rng.uniform01()) : 0.0f;
      PrimarySample& ps = prim_[p * 8 + k];
      ps.px = x + jx;
      ps.py = y + jy;
      camera_ray(ps.px, ps.py, lu, lv, ps.origin, ps.dir);
      set_ray(hits_[p].ray, k, ps.origin, ps.dir, kInf);
      hits_[p].hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
    }
  }
}

void Renderer::TileIntegrator::trace_primary() {
  const auto t0 = Clock::now();
  for (int p = 0; p < kPackets; ++p) {
    if (valid_[p].count() > 0)
      rtcIntersect8(valid_[p].data(), r_.rtc_scene_, &coherent_, &hits_[p]);
  }
  trace_ns_ += std::chrono::duration<double, std::nano>(Clock::now() - t0).count();
}

// Ground truth from pixel-centre pinhole rays (the sample-0 rays when there is no lens).
void Renderer::TileIntegrator::store_ground_truth(FrameBuffers& out) const {
  for (int p = 0; p < kPackets; ++p) {
    for (int k = 0; k < 8; ++k) {
      if (!valid_[p][k]) continue;
      int x, y;
      pixel_of(p * 8 + k, x, y);
      const RTCRayHit8& rh = hits_[p];
      if (rh.hit.geomID[k] == RTC_INVALID_GEOMETRY_ID) {
        out.depth.at<float>(y, x) = 0.0f;  // background: no depth, id 0, no normal
        out.instance.at<std::uint16_t>(y, x) = 0;
        out.semantic.at<std::uint16_t>(y, x) = 0;
        out.normals.at<cv::Vec3f>(y, x) = cv::Vec3f(0, 0, 0);
        continue;
      }
      const Geometry& g = r_.geometries_[rh.hit.geomID[k]];
      const Eigen::Vector3f d(rh.ray.dir_x[k], rh.ray.dir_y[k], rh.ray.dir_z[k]);
      out.depth.at<float>(y, x) = rh.ray.tfar[k] * d.dot(forward_);
      out.instance.at<std::uint16_t>(y, x) = g.instance_id;
      out.semantic.at<std::uint16_t>(y, x) = g.semantic_id;
      Eigen::Vector3f n =
          Eigen::Vector3f(rh.hit.Ng_x[k], rh.hit.Ng_y[k], rh.hit.Ng_z[k]).normalized();
      if (!g.normals.empty()) {
        const auto& tri = g.triangles[rh.hit.primID[k]];
        const float u = rh.hit.u[k], v = rh.hit.v[k];
        const Eigen::Vector3f s =
            (1 - u - v) * g.normals[tri[0]] + u * g.normals[tri[1]] + v * g.normals[tri[2]];
        if (s.squaredNorm() > 1e-12f) n = s.normalized();
      }
      if (n.dot(d) > 0) n = -n;
      const Eigen::Vector3f nc = rot_.transpose() * n;
      out.normals.at<cv::Vec3f>(y, x) = cv::Vec3f(nc.x(), nc.y(), nc.z());
    }
  }
}

// Shades packet p of sample s: the background for misses, else the surface, the lights it
// samples, their shadow rays and the sums they go to.
void Renderer::TileIntegrator::shade_packet(int p, int s) {
  ShadowRays shadows;
  for (RTCRay8& packet : shadows.rays) switch_off_lanes(packet);
  for (int k = 0; k < 8; ++k) {
    if (!valid_[p][k]) continue;
    const int li = p * 8 + k;
    if (hits_[p].hit.geomID[k] == RTC_INVALID_GEOMETRY_ID) {
      const PrimarySample& ps = prim_[li];
      own_[li] += r_.background(ps.px, ps.py, ps.dir);
      continue;
    }
    const SurfacePoint at = surface_at(p, k);
    shadows.albedos[k] = at.albedo;
    if (s == 0) {
      surface0_[li] = at.surface;
      normal0_[li] = at.normal;
      position0_[li] = at.position;
    }
    const bool reuse =
        s == 0 || (at.surface == surface0_[li] && at.normal.dot(normal0_[li]) > kReuseNormalCos);
    if (reuse) {
      albedo_sum_[li] += at.albedo;
      ++reuse_count_[li];
      if (s >= options_.light_samples) continue;  // lit once for the pixel, not per sample
      ++light_count_[li];
    }
    shadows.into_pixel[k] = reuse;
    sample_lights(p, k, s, at, shadows);
  }
  resolve_shadows(p, shadows);
}

Renderer::TileIntegrator::SurfacePoint Renderer::TileIntegrator::surface_at(int p, int k) const {
  const PrimarySample& ps = prim_[p * 8 + k];
  const RTCRayHit8& rh = hits_[p];
  SurfacePoint at;
  at.surface = static_cast<int>(rh.hit.geomID[k]);
  const Geometry& g = r_.geometries_[at.surface];
  const auto& tri = g.triangles[rh.hit.primID[k]];
  const float u = rh.hit.u[k], v = rh.hit.v[k], bw = 1 - u - v;
  at.position = ps.origin + rh.ray.tfar[k] * ps.dir;
  Eigen::Vector3f ng = Eigen::Vector3f(rh.hit.Ng_x[k], rh.hit.Ng_y[k], rh.hit.Ng_z[k]).normalized();
  if (ng.dot(ps.dir) > 0) ng = -ng;
  Eigen::Vector3f n = ng;
  if (!g.normals.empty()) {
    const Eigen::Vector3f sn =
        bw * g.normals[tri[0]] + u * g.normals[tri[1]] + v * g.normals[tri[2]];
    if (sn.squaredNorm() > 1e-12f) n = sn.normalized();
    if (n.dot(ps.dir) > 0) n = -n;
  }
  at.geometric_normal = ng;
  at.normal = n;
  Eigen::Vector2f uv = Eigen::Vector2f::Zero();
  if (!g.uvs.empty()) uv = bw * g.uvs[tri[0]] + u * g.uvs[tri[1]] + v * g.uvs[tri[2]];
  at.material = &r_.scene_.materials[g.material];
  const TextureSampler& texture = r_.material_textures_[g.material];
  const float footprint = texture.filters_detail() && !g.uvs.empty()
                              ? uv_footprint(g, tri, rh.ray.tfar[k], n.dot(ps.dir), pixel_angle_)
                              : 0.0f;
  Eigen::Vector3f albedo = at.material->diffuse.cwiseProduct(texture.at(uv.x(), uv.y(), footprint));
  if (at.material->hue_offset_deg != 0.0f)
    albedo = (r_.hue_rotations_[g.material] * albedo).cwiseMax(0.0f);
  at.albedo = albedo.cwiseMin(1.0f);
  return at;
}

// One shadow ray per light kind the scene has, from just above the surface.
void Renderer::TileIntegrator::sample_lights(int p, int k, int s, const SurfacePoint& at,
                                             ShadowRays& shadows) {
  const int li = p * 8 + k;
  RandomStream& rng = *streams_[li];
  int px, py;
  pixel_of(li, px, py);
  if (!strata_block_) strata_block_ = strata_.block(tile_x_ * kTile, tile_y_ * kTile, s);
  const float eps = 1e-4f * (1.0f + at.position.cwiseAbs().maxCoeff());
  const Eigen::Vector3f origin = at.position + eps * at.geometric_normal;
  const Eigen::Vector3f& view = prim_[li].dir;
  if (sun_on_) sample_sun(k, px, py, origin, at, view, shadows);
  if (!r_.lights_on_.empty()) sample_point_light(k, px, py, rng, origin, at, view, shadows);
  if (env_on_) sample_environment(k, px, py, rng, origin, at, shadows);
}

// Light × cos through shadow ray (q, k), split into the part the albedo scales and the
// specular part.
void Renderer::TileIntegrator::add_light(ShadowRays& shadows, int q, int k,
                                         const Eigen::Vector3f& l, float cos_l,
                                         const Eigen::Vector3f& radiance, const SurfacePoint& at,
                                         const Eigen::Vector3f& view) const {
  const scene::Material& m = *at.material;
  shadows.to_diffuse[q][k] = radiance * cos_l;
  shadows.to_specular[q][k] = Eigen::Vector3f::Zero();
  if (m.specular > 0) {
    const Eigen::Vector3f hv = (l - view).normalized();
    shadows.to_specular[q][k] =
        radiance * (m.specular * std::pow(std::max(0.0f, at.normal.dot(hv)), m.shininess) * cos_l);
  }
}

// A uniform direction in the sun's cone (soft shadows).
void Renderer::TileIntegrator::sample_sun(int k, int px, int py, const Eigen::Vector3f& origin,
                                          const SurfacePoint& at, const Eigen::Vector3f& view,
                                          ShadowRays& shadows) const {
  const auto [r1, r2] = strata_block_->point(px, py, 0);
  const float ct = 1.0f - r1 * (1.0f - sun_cos_max_);
  const float st = std::sqrt(std::max(0.0f, 1 - ct * ct)), ph = 2 * kPi * r2;
  // Unit by construction (orthonormal basis, ct² + st² = 1): no normalisation.
  const Eigen::Vector3f l = ct * sun_dir_ + st * std::cos(ph) * sun_u_ + st * std::sin(ph) * sun_v_;
  const float c = at.normal.dot(l);
  if (c > 0 && at.geometric_normal.dot(l) > 0) {
    set_ray(shadows.rays[0], k, origin, l, kInf);
    shadows.valid[0][k] = -1;
    const auto& sun = r_.scene_.sun;
    add_light(shadows, 0, k, l, c, sun.color * sun.intensity, at, view);
  }
}

// One point light per sample. Up to kLocalLights lights are chosen in proportion to their
// unshadowed contribution here (power / distance² × a floored cosine, so every light keeps a
// chance and the estimate stays unbiased); far and back-facing lights then rarely waste the
// sample, which removes most of the speckle. More lights: by power.
void Renderer::TileIntegrator::sample_point_light(int k, int px, int py, RandomStream& rng,
                                                  const Eigen::Vector3f& origin,
                                                  const SurfacePoint& at,
                                                  const Eigen::Vector3f& view,
                                                  ShadowRays& shadows) const {
  const Eigen::Vector3f& n = at.normal;
  const auto [pick, light_z] = strata_block_->point(px, py, 1);
  const int on = static_cast<int>(r_.lights_on_.size());
  int jj = 0;
  float prob = 0;
  if (on <= kLocalLights) {
    std::array<float, kLocalLights> cdf{};
    float total = 0;
    for (int i = 0; i < on; ++i) {
      const auto& li = r_.scene_.point_lights[r_.lights_on_[i]];
      const Eigen::Vector3f d = li.position - origin;
      const float d2 = std::max(d.squaredNorm(), 1e-4f);
      const float cosine = std::max(0.0f, n.dot(d) / std::sqrt(d2));
      total += r_.light_power_[i] / d2 * (cosine + 0.05f);
      cdf[i] = total;
    }
    const float target = pick * total;
    while (jj < on - 1 && cdf[jj] <= target) ++jj;
    prob = (cdf[jj] - (jj > 0 ? cdf[jj - 1] : 0.0f)) / total;
  } else {
    const auto& light_cdf = r_.light_cdf_;
    const int j = static_cast<int>(std::lower_bound(light_cdf.begin(), light_cdf.end(), pick) -
                                   light_cdf.begin());
    jj = std::min(j, on - 1);
    prob = light_cdf[jj] - (jj > 0 ? light_cdf[jj - 1] : 0.0f);
  }
  const auto& light = r_.scene_.point_lights[r_.lights_on_[jj]];
  const float z = 1.0f - 2.0f * light_z;
  const float ph = 2 * kPi * static_cast<float>(rng.uniform01());
  const float rr = std::sqrt(std::max(0.0f, 1 - z * z));
  const Eigen::Vector3f q =
      light.position + light.radius * Eigen::Vector3f(rr * std::cos(ph), rr * std::sin(ph), z);
  const Eigen::Vector3f to = q - origin;
  const float dist = to.norm();
  if (!(dist > 1e-6f)) return;
  const Eigen::Vector3f l = to / dist;
  const float c = n.dot(l);
  if (c > 0 && at.geometric_normal.dot(l) > 0 && prob > 0) {
    set_ray(shadows.rays[1], k, origin, l, dist);
    shadows.valid[1][k] = -1;
    add_light(shadows, 1, k, l, c,
              light.color * (light.intensity / (std::max(dist * dist, 1e-4f) * prob)), at, view);
  }
}

// The sky. An environment map: one-sample MIS of two strategies, half the samples drawn by the
// map's brightness (finds the sun), half cosine-weighted (covers the hemisphere when the bright
// part is behind the surface); pdf = the mixture's, so either choice gives albedo / π × L × cos
// / pdf. A uniform sky: a cosine-weighted direction; the estimator is albedo × L_env.
void Renderer::TileIntegrator::sample_environment(int k, int px, int py, RandomStream& rng,
                                                  const Eigen::Vector3f& origin,
                                                  const SurfacePoint& at,
                                                  ShadowRays& shadows) const {
  const Eigen::Vector3f& n = at.normal;
  if (!r_.env_row_cdf_.empty()) {
    const float r0 = static_cast<float>(rng.uniform01());
    const auto [r1, r2] = strata_block_->point(px, py, 2);
    Eigen::Vector3f l;
    if (r0 < 0.5f) {
      float ignored = 0;
      l = r_.sample_environment(r1, r2, ignored);
    } else {
      Eigen::Vector3f bu, bv;
      basis(n, bu, bv);
      const float rad = std::sqrt(r1), ph = 2 * kPi * r2;
      l = rad * std::cos(ph) * bu + rad * std::sin(ph) * bv +
          std::sqrt(std::max(0.0f, 1 - r1)) * n;  // unit by construction
    }
    const float c = n.dot(l);
    const float pdf = 0.5f * r_.environment_pdf(l) + 0.5f * std::max(0.0f, c) / kPi;
    if (pdf > 0 && c > 0 && at.geometric_normal.dot(l) > 0) {
      set_ray(shadows.rays[2], k, origin, l, kInf);
      shadows.valid[2][k] = -1;
      shadows.to_diffuse[2][k] = r_.environment_lighting(l) * (c / (kPi * pdf));
      shadows.to_specular[2][k] = Eigen::Vector3f::Zero();
    }
    return;
  }
  const auto [r1, r2] = strata_block_->point(px, py, 2);
  Eigen::Vector3f bu, bv;
  basis(n, bu, bv);
  const float rad = std::sqrt(r1), ph = 2 * kPi * r2;
  const Eigen::Vector3f l = rad * std::cos(ph) * bu + rad * std::sin(ph) * bv +
                            std::sqrt(std::max(0.0f, 1 - r1)) * n;  // unit
  if (at.geometric_normal.dot(l) > 0) {
    set_ray(shadows.rays[2], k, origin, l, kInf);
    shadows.valid[2][k] = -1;
    shadows.to_diffuse[2][k] = r_.environment(l);
    shadows.to_specular[2][k] = Eigen::Vector3f::Zero();
  }
}

// Traces the packet's shadow rays; each unoccluded one adds its light to the pixel's sums
// (the sun's apart) or, for a sample lit on its own, its radiance to the sample.
void Renderer::TileIntegrator::resolve_shadows(int p, ShadowRays& shadows) {
  for (int q = 0; q < 3; ++q) {
    const int n = shadows.valid[q].count();
    if (n == 0) continue;
    // Sun rays are parallel and start close together: coherent.
    rtcOccluded8(shadows.valid[q].data(), r_.rtc_scene_, q == 0 ? &coherent_ : &incoherent_,
                 &shadows.rays[q]);
    ray_count_ += n;
    for (int k = 0; k < 8; ++k) {
      // Embree sets tfar to −inf for occluded rays.
      if (!shadows.valid[q][k] || shadows.rays[q].tfar[k] < 0.0f) continue;
      const int li = p * 8 + k;
      if (shadows.into_pixel[k] && q == 0) {
        sun_diffuse_[li] += shadows.to_diffuse[q][k];
        sun_specular_[li] += shadows.to_specular[q][k];
      } else if (shadows.into_pixel[k]) {
        diffuse_[li] += shadows.to_diffuse[q][k];
        specular_[li] += shadows.to_specular[q][k];
      } else {
        own_[li] +=
            shadows.albedos[k].cwiseProduct(shadows.to_diffuse[q][k]) + shadows.to_specular[q][k];
      }
    }
  }
}

// What the pass leaves per pixel: the reuse sums for the final mix and later passes, and, in
// pass 1, the stream positions, edge colours, guide and mean lighting.
void Renderer::TileIntegrator::store_lighting(PixelLighting& lighting) const {
  for (int li = 0; li < active_; ++li) {
    int x, y;
    pixel_of(li, x, y);
    const std::size_t i = index_of(x, y);
    PixelLighting::Reuse& reuse = lighting.reuse[i];
    // Every field is written, background pixels included: the buffers come from a pool.
    for (int c = 0; c < 3; ++c) {
      reuse.own[c] = own_[li][c];
      reuse.albedo_sum[c] = albedo_sum_[li][c];
    }
    reuse.count = static_cast<float>(reuse_count_[li]);
    reuse.samples = static_cast<float>(sample_end_);
    if (sample_begin_ > 0) continue;  // the lighting, guide and stream positions are pass 1's
    lighting.stream_positions[i] = streams_[li]->position();
    // What edge detection compares: the mean albedo of the reusing samples, else the mean
    // radiance of the others (background).
    const Eigen::Vector3f color = reuse_count_[li] > 0
                                      ? Eigen::Vector3f(albedo_sum_[li] / reuse_count_[li])
                                      : Eigen::Vector3f(own_[li] / sample_end_);
    for (int c = 0; c < 3; ++c) lighting.first_color[c][i] = color[c];
    const float inv = 1.0f / static_cast<float>(std::max(1, light_count_[li]));
    GuidePlanes& guide = lighting.guide;
    PixelLight& light = lighting.light[i];
    guide.surface[i] = surface0_[li];
    for (int c = 0; c < 3; ++c) {
      guide.geometry[c][i] = normal0_[li][c];
      guide.geometry[3 + c][i] = position0_[li][c];
      light.diffuse[c] = diffuse_[li][c] * inv;
      light.specular[c] = specular_[li][c] * inv;
      reuse.sun.diffuse[c] = sun_diffuse_[li][c] * inv;
      reuse.sun.specular[c] = sun_specular_[li][c] * inv;
    }
  }
}

void Renderer::render_tile(int tile_x, int tile_y, int sample_begin, int sample_end,
                           const std::uint8_t* refine, const RenderOptions& options,
                           FrameBuffers& out, PixelLighting& lighting, double& trace_ns,
                           double& shade_ns, long long& ray_count) const {
  TileIntegrator tile(*this, tile_x, tile_y, sample_begin, sample_end, options, trace_ns, shade_ns,
                      ray_count);
  tile.run(refine, out, lighting);
}

RayQuery Renderer::cast(const Eigen::Vector3f& origin, const Eigen::Vector3f& direction,
                        float max_distance) const {
  RayQuery q;
  const float len = direction.norm();
  if (len <= 0) return q;
  const Eigen::Vector3f d = direction / len;
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRayHit rh{};
  rh.ray.org_x = origin.x();
  rh.ray.org_y = origin.y();
  rh.ray.org_z = origin.z();
  rh.ray.dir_x = d.x();
  rh.ray.dir_y = d.y();
  rh.ray.dir_z = d.z();
  rh.ray.tnear = 0.0f;
  rh.ray.tfar = max_distance;
  rh.ray.mask = 0xFFFFFFFFu;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(rtc_scene_, &ctx, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return q;
  q.hit = true;
  q.distance = rh.ray.tfar;
  q.position = origin + rh.ray.tfar * d;
  q.instance_index = static_cast<int>(rh.hit.geomID);
  q.instance_id = geometries_[rh.hit.geomID].instance_id;
  q.semantic_id = geometries_[rh.hit.geomID].semantic_id;
  return q;
}

RayQuery Renderer::first_hit_toward(const Eigen::Vector3f& point) const {
  return cast(scene_.camera.position, point - scene_.camera.position);
}

}  // namespace wheelpose::render
