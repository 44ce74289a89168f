// Renderer::TileIntegrator (renderer_internal.h): one tile's samples, step by step.

#include <algorithm>
#include <string>

#include "render/renderer_internal.h"
#include "render/strands.h"
#include "scene/scene.h"

namespace wheelpose::render {

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
  bounce_.fill(Eigen::Vector3f::Zero());
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

Eigen::Vector2f Renderer::TileIntegrator::image_motion(const Geometry& g, unsigned prim, float u,
                                                       float v,
                                                       const Eigen::Vector3f& offset) const {
  if (g.motion.empty()) return Eigen::Vector2f::Zero();
  const auto& tri = g.triangles[prim];
  const Eigen::Vector3f travel =
      (1 - u - v) * g.motion[tri[0]] + u * g.motion[tri[1]] + v * g.motion[tri[2]];
  // Where the point is when the shutter opens and when it closes, seen from the camera.
  const Eigen::Vector3f open = rot_.transpose() * (offset - 0.5f * travel);
  const Eigen::Vector3f close = rot_.transpose() * (offset + 0.5f * travel);
  if (open.z() >= -1e-3f || close.z() >= -1e-3f) return Eigen::Vector2f::Zero();
  const float f = 0.5f * static_cast<float>(h_) / tan_half_;
  return f * Eigen::Vector2f(close.x() / -close.z() - open.x() / -open.z(),
                             open.y() / -open.z() - close.y() / -close.z());
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
        if (!out.motion.empty()) out.motion.at<cv::Vec2f>(y, x) = cv::Vec2f(0, 0);
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
      if (!out.motion.empty()) {
        const Eigen::Vector2f m =
            image_motion(g, rh.hit.primID[k], rh.hit.u[k], rh.hit.v[k], rh.ray.tfar[k] * d);
        out.motion.at<cv::Vec2f>(y, x) = cv::Vec2f(m.x(), m.y());
      }
    }
  }
}

// Shades packet p of sample s: the background for misses, else the surface, the lights it
// samples, their shadow rays and the sums they go to.
void Renderer::TileIntegrator::shade_packet(int p, int s) {
  ShadowRays shadows;
  for (RTCRay8& packet : shadows.rays) switch_off_lanes(packet);
  alignas(32) RTCRayHit8 bounce;
  PacketMask bounce_valid{};
  if (options_.bounce) switch_off_lanes(bounce.ray);
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
    if (options_.bounce) {
      RandomStream& rng = *streams_[li];
      const float r1 = static_cast<float>(rng.uniform01()),
                  r2 = static_cast<float>(rng.uniform01());
      const Eigen::Vector3f l = cosine_direction(at.normal, r1, r2);
      if (at.geometric_normal.dot(l) > 0) {
        const float eps = 1e-4f * (1.0f + at.position.cwiseAbs().maxCoeff());
        set_ray(bounce.ray, k, at.position + eps * at.geometric_normal, l, kInf);
        bounce.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
        bounce_valid[k] = -1;
      }
    }
  }
  resolve_shadows(p, shadows);
  if (bounce_valid.count() > 0) add_bounce(p, bounce, bounce_valid, shadows);
}

void Renderer::TileIntegrator::add_bounce(int p, RTCRayHit8& rays, PacketMask valid,
                                          const ShadowRays& primary) {
  const auto t0 = Clock::now();
  rtcIntersect8(valid.data(), r_.rtc_scene_, &incoherent_, &rays);
  trace_ns_ += std::chrono::duration<double, std::nano>(Clock::now() - t0).count();
  ray_count_ += valid.count();
  ShadowRays second;
  for (RTCRay8& packet : second.rays) switch_off_lanes(packet);
  for (int k = 0; k < 8; ++k) {
    if (!valid[k] || rays.hit.geomID[k] == RTC_INVALID_GEOMETRY_ID) continue;
    const Eigen::Vector3f origin(rays.ray.org_x[k], rays.ray.org_y[k], rays.ray.org_z[k]);
    const Eigen::Vector3f dir(rays.ray.dir_x[k], rays.ray.dir_y[k], rays.ray.dir_z[k]);
    const SurfacePoint at = surface_of(rays, k, origin, dir, 0.0f);
    second.albedos[k] = at.albedo;
    RandomStream& rng = *streams_[p * 8 + k];
    const float eps = 1e-4f * (1.0f + at.position.cwiseAbs().maxCoeff());
    const Eigen::Vector3f from = at.position + eps * at.geometric_normal;
    const auto pair = [&] {
      const float a = static_cast<float>(rng.uniform01());
      return std::array<float, 2>{a, static_cast<float>(rng.uniform01())};
    };
    if (sun_on_) sample_sun(k, pair(), from, at, dir, second);
    if (!r_.lights_on_.empty()) {
      sample_point_light(k, pair(), rng, from, at, dir, second,
                         kBounceMinLightDistance * kBounceMinLightDistance);
    }
  }
  for (int q = 0; q < 2; ++q) {
    const int n = second.valid[q].count();
    if (n == 0) continue;
    rtcOccluded8(second.valid[q].data(), r_.rtc_scene_, &incoherent_, &second.rays[q]);
    ray_count_ += n;
    for (int k = 0; k < 8; ++k) {
      if (!second.valid[q][k] || second.rays[q].tfar[k] < 0.0f) continue;
      // The bounce surface's radiance toward the sample; a cosine-weighted direction makes it
      // the estimate of the light arriving there, in the units of the direct light.
      const Eigen::Vector3f arriving = second.albedos[k].cwiseProduct(second.to_diffuse[q][k]);
      const int li = p * 8 + k;
      if (primary.into_pixel[k]) {
        bounce_[li] += arriving;
      } else {
        own_[li] += primary.albedos[k].cwiseProduct(arriving);
      }
    }
  }
}

Renderer::TileIntegrator::SurfacePoint Renderer::TileIntegrator::surface_at(int p, int k) const {
  const PrimarySample& ps = prim_[p * 8 + k];
  return surface_of(hits_[p], k, ps.origin, ps.dir, pixel_angle_);
}

Renderer::TileIntegrator::SurfacePoint Renderer::TileIntegrator::surface_of(
    const RTCRayHit8& rh, int k, const Eigen::Vector3f& origin, const Eigen::Vector3f& dir,
    float pixel_angle) const {
  SurfacePoint at;
  at.surface = static_cast<int>(rh.hit.geomID[k]);
  const Geometry& g = r_.geometries_[at.surface];
  const auto& tri = g.triangles[rh.hit.primID[k]];
  const float u = rh.hit.u[k], v = rh.hit.v[k], bw = 1 - u - v;
  at.position = origin + rh.ray.tfar[k] * dir;
  Eigen::Vector3f ng = Eigen::Vector3f(rh.hit.Ng_x[k], rh.hit.Ng_y[k], rh.hit.Ng_z[k]).normalized();
  if (ng.dot(dir) > 0) ng = -ng;
  Eigen::Vector3f n = ng;
  if (!g.normals.empty()) {
    const Eigen::Vector3f sn =
        bw * g.normals[tri[0]] + u * g.normals[tri[1]] + v * g.normals[tri[2]];
    if (sn.squaredNorm() > 1e-12f) n = sn.normalized();
    if (n.dot(dir) > 0) n = -n;
  }
  at.geometric_normal = ng;
  at.normal = n;
  Eigen::Vector2f uv = Eigen::Vector2f::Zero();
  if (!g.uvs.empty()) uv = bw * g.uvs[tri[0]] + u * g.uvs[tri[1]] + v * g.uvs[tri[2]];
  at.material = &r_.scene_.materials[g.material];
  const TextureSampler& texture = r_.material_textures_[g.material];
  const float footprint = texture.filters_detail() && !g.uvs.empty() && pixel_angle > 0
                              ? uv_footprint(g, tri, rh.ray.tfar[k], n.dot(dir), pixel_angle)
                              : 0.0f;
  Eigen::Vector3f albedo = at.material->diffuse.cwiseProduct(texture.at(uv.x(), uv.y(), footprint));
  if (g.strands_per_uv > 0)
    albedo *= strand_at(uv.x(), uv.y(), g.strands_per_uv, g.strand_coverage).shade;
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
  if (sun_on_) sample_sun(k, strata_block_->point(px, py, 0), origin, at, view, shadows);
  if (!r_.lights_on_.empty()) {
    sample_point_light(k, strata_block_->point(px, py, 1), rng, origin, at, view, shadows, 1e-4f);
  }
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
void Renderer::TileIntegrator::sample_sun(int k, std::array<float, 2> u,
                                          const Eigen::Vector3f& origin, const SurfacePoint& at,
                                          const Eigen::Vector3f& view, ShadowRays& shadows) const {
  const auto [r1, r2] = u;
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
void Renderer::TileIntegrator::sample_point_light(int k, std::array<float, 2> u, RandomStream& rng,
                                                  const Eigen::Vector3f& origin,
                                                  const SurfacePoint& at,
                                                  const Eigen::Vector3f& view, ShadowRays& shadows,
                                                  float min_distance_squared) const {
  const Eigen::Vector3f& n = at.normal;
  const auto [pick, light_z] = u;
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
    add_light(
        shadows, 1, k, l, c,
        light.color * (light.intensity / (std::max(dist * dist, min_distance_squared) * prob)), at,
        view);
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
      l = cosine_direction(n, r1, r2);
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
  const Eigen::Vector3f l = cosine_direction(n, r1, r2);
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
    if (!lighting.bounce.empty()) {
      PixelLight& bounce = lighting.bounce[i];
      for (int c = 0; c < 3; ++c) {
        bounce.diffuse[c] = bounce_[li][c] * inv;
        bounce.specular[c] = 0.0f;
      }
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

}  // namespace wheelpose::render
