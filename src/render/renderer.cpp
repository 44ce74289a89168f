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
#include "render/renderer_internal.h"
#include "render/strands.h"
#include "render/strata.h"

namespace wheelpose::render {

namespace {

// Embree filter of a hair card's hits: a hit between two strands is no hit, so the ray goes on
// to the layers and the surfaces behind (render/strands.h).
void pass_between_strands(const RTCFilterFunctionNArguments* args) {
  const auto& g = *static_cast<const Renderer::Geometry*>(args->geometryUserPtr);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    const auto& tri = g.triangles[RTCHitN_primID(args->hit, args->N, i)];
    const float u = RTCHitN_u(args->hit, args->N, i), v = RTCHitN_v(args->hit, args->N, i);
    const Eigen::Vector2f uv = (1 - u - v) * g.uvs[tri[0]] + u * g.uvs[tri[1]] + v * g.uvs[tri[2]];
    if (!strand_at(uv.x(), uv.y(), g.strands_per_uv, g.strand_coverage).covered) {
      args->valid[i] = 0;
    }
  }
}

double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
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
    g.motion.reserve(mesh.motion.size());
    for (const auto& m : mesh.motion) g.motion.push_back(xf.linear() * m);
    const scene::Material& material = scene_.materials[in.material];
    if (material.strands_per_uv > 0 && !g.uvs.empty()) {
      g.strands_per_uv = material.strands_per_uv;
      g.strand_coverage = material.strand_coverage;
      // Every query (camera, shadow, bounce and label rays) passes between the strands.
      rtcSetGeometryUserData(geom, &g);
      rtcSetGeometryIntersectFilterFunction(geom, pass_between_strands);
      rtcSetGeometryOccludedFilterFunction(geom, pass_between_strands);
    }
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
  const bool moving = std::any_of(geometries_.begin(), geometries_.end(),
                                  [](const Geometry& g) { return !g.motion.empty(); });
  if (moving) out.motion = cv::Mat(h, w, CV_32FC2);
  // The decoupled-shading buffers (≈ 140 MB at 1280×720) come from a pool shared by all
  // renderers: allocating them afresh each frame made the kernel fault in and zero every page.
  static BufferPool<PixelLighting> pool;
  std::unique_ptr<PixelLighting> pooled = pool.acquire();
  PixelLighting& lighting = *pooled;
  const std::size_t pixels = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  lighting.guide.resize(pixels);
  lighting.stream_positions.resize(pixels);
  lighting.light.resize(pixels);
  lighting.bounce.resize(options.bounce ? pixels : 0);
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
  if (options.bounce) {
    // The bounce over three times the direct light's window: indirect light varies slowly.
    const int radius = std::min(3 * options.denoise_radius, RenderOptions::kMaxDenoiseRadius);
    if (radius > 0) {
      denoise_lighting(w, h, lighting.guide, radius, lighting.bounce, lighting.denoise_scratch);
    }
    for (std::size_t i = 0; i < pixels; ++i) {
      for (int c = 0; c < 3; ++c) lighting.light[i].diffuse[c] += lighting.bounce[i].diffuse[c];
    }
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
                                      scene_.camera.focus_distance, scene_.seed, out.motion)
                         : encode_srgb(out.linear);
  timings_.post_ms = ms_since(post_start);
  return out;
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
