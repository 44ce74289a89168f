// Renderer benchmarks: (a) ray throughput, (b) a frame like the paper's at 1280×720 — 8 people of
// ≈ 40k triangles (subdivided capsules and a box as stand-ins for body and wheelchair), 25
// textured occluders, a textured background wall, sun + 7 point lights and a sky — at 1 and
// 4 spp, broken down into build, trace, shade, edge marking, denoise, post and encode times
// (counters, in ms); render_ms is the frame without the encoding; BM_PaperFrameUnlit is the same
// frame with no light at all, the floor under the lighting; BM_PaperFrameError is the frame's error
// against a 64-spp reference; (c) the per-frame image passes alone:
// BM_Denoise (lighting smoothing) and BM_MarkEdges (adaptive anti-aliasing's edge marking).
//
// Run: build/<dir>/bench/bench_render [--benchmark_filter=...]

#include <benchmark/benchmark.h>

#include <cmath>
#include <filesystem>
#include <opencv2/imgproc.hpp>
#include <string>

#include "core/random.h"
#include "render/adaptive.h"
#include "render/denoise.h"
#include "render/frame_io.h"
#include "render/renderer.h"
#include "scene/primitives.h"

namespace {

using namespace wheelpose;

// One seated-person stand-in: torso, head, upper/lower arms and legs as capsules, wheelchair box.
void add_person(scene::Scene& s, int first_mesh, int material, const Eigen::Affine3f& at,
                std::uint16_t id) {
  struct Part {
    int mesh;
    Eigen::Vector3f pos;
    Eigen::Vector3f rot_deg;
  };
  const Part parts[] = {
      {0, {0, 0.95f, 0}, {0, 0, 0}},           {1, {0, 1.55f, 0}, {0, 0, 0}},
      {2, {-0.25f, 1.1f, 0.1f}, {-30, 0, 10}}, {2, {0.25f, 1.1f, 0.1f}, {-30, 0, -10}},
      {2, {-0.3f, 0.85f, 0.3f}, {-80, 0, 0}},  {2, {0.3f, 0.85f, 0.3f}, {-80, 0, 0}},
      {3, {-0.12f, 0.55f, 0.25f}, {90, 0, 0}}, {3, {0.12f, 0.55f, 0.25f}, {90, 0, 0}},
      {3, {-0.12f, 0.25f, 0.45f}, {0, 0, 0}},  {3, {0.12f, 0.25f, 0.45f}, {0, 0, 0}},
      {4, {0, 0.45f, 0.1f}, {12.49f, 0, 0}},
  };
  for (const Part& p : parts) {
    scene::Instance in;
    in.mesh = first_mesh + p.mesh;
    in.material = p.mesh == 4 ? 0 : material;
    const float k = 3.14159265f / 180.0f;
    const Eigen::Affine3f local = Eigen::Translation3f(p.pos) *
                                  Eigen::AngleAxisf(p.rot_deg.z() * k, Eigen::Vector3f::UnitZ()) *
                                  Eigen::AngleAxisf(p.rot_deg.x() * k, Eigen::Vector3f::UnitX());
    in.transform = (at * local).matrix();
    in.instance_id = id;
    in.semantic_id = 1;
    s.instances.push_back(in);
  }
}

scene::Scene paper_scene() {
  scene::Scene s;
  s.seed = 539662031;
  s.camera.position = Eigen::Vector3f(0, 0, 15);
  s.camera.vfov_deg = 45;  // 1280×720 is the default
  RandomStream rng(1, {"bench", "paper_scene"});

  // Meshes 0–4: body parts and wheelchair (≈ 40k triangles per person), 5–6: occluders, 7: wall.
  s.meshes.push_back(scene::make_capsule(0.18f, 0.2f, 40));        // torso
  s.meshes.push_back(scene::make_sphere(0.12f, 40));               // head
  s.meshes.push_back(scene::make_capsule(0.05f, 0.12f, 24));       // arm segment
  s.meshes.push_back(scene::make_capsule(0.07f, 0.15f, 24));       // leg segment
  s.meshes.push_back(scene::make_box({0.35f, 0.35f, 0.35f}, 16));  // wheelchair placeholder
  s.meshes.push_back(scene::make_box({0.5f, 0.5f, 0.5f}, 2));
  s.meshes.push_back(scene::make_sphere(0.5f, 24));
  s.meshes.push_back(scene::make_box({15, 15, 0.05f}, 1));

  scene::Material chair;
  chair.diffuse = {0.2f, 0.2f, 0.22f};
  chair.specular = 0.3f;
  s.materials.push_back(chair);
  const scene::TextureKind kinds[] = {scene::TextureKind::kNoise,   scene::TextureKind::kStripes,
                                      scene::TextureKind::kChecker, scene::TextureKind::kFabric,
                                      scene::TextureKind::kWood,    scene::TextureKind::kMarble};
  for (int i = 0; i < 6; ++i) {
    scene::Material m;
    m.texture.kind = kinds[i];
    m.texture.color_a =
        Eigen::Vector3f(rng.uniform(0.2, 1), rng.uniform(0.2, 1), rng.uniform(0.2, 1));
    m.texture.color_b = m.texture.color_a * 0.3f;
    m.texture.scale = 4;
    m.hue_offset_deg = static_cast<float>(rng.uniform(-180, 180));
    s.materials.push_back(m);
  }
  scene::Material wall;
  const std::string image =
      std::string(WHEELPOSE_SHARED_DIR) + "/assets/makehuman/skins/litsphere_caucasian.png";
  if (std::filesystem::exists(image)) {
    wall.texture.kind = scene::TextureKind::kImage;
    wall.texture.path = image;
  } else {
    wall.texture.kind = scene::TextureKind::kMarble;
  }
  s.materials.push_back(wall);

  for (int p = 0; p < 8; ++p) {
    const Eigen::Affine3f at =
        Eigen::Translation3f(rng.uniform(-5, 5), rng.uniform(-4, 2), rng.uniform(-6, 4)) *
        Eigen::AngleAxisf(static_cast<float>(rng.uniform(0, 6.283)), Eigen::Vector3f::UnitY()) *
        Eigen::Scaling(static_cast<float>(rng.uniform(1.0, 2.5)));
    add_person(s, 0, 1 + p % 6, at, static_cast<std::uint16_t>(p + 1));
  }
  for (int o = 0; o < 25; ++o) {
    scene::Instance in;
    in.mesh = 5 + o % 2;
    in.material = 1 + o % 6;
    const Eigen::Affine3f at =
        Eigen::Translation3f(rng.uniform(-7.5, 7.5), rng.uniform(-7.5, 7.5), rng.uniform(-10, 4)) *
        Eigen::AngleAxisf(static_cast<float>(rng.uniform(0, 6.283)),
                          Eigen::Vector3f(1, 1, 0).normalized()) *
        Eigen::Scaling(static_cast<float>(rng.uniform(1, 3)));
    in.transform = at.matrix();
    in.instance_id = static_cast<std::uint16_t>(100 + o);
    in.semantic_id = 2;
    s.instances.push_back(in);
  }
  scene::Instance w;
  w.mesh = 7;
  w.material = 7;
  w.transform.topRightCorner<3, 1>() = Eigen::Vector3f(0, 0, -10);
  w.instance_id = 200;
  w.semantic_id = 3;
  s.instances.push_back(w);

  s.sun.solar = scene::SolarPosition{14.0f, 200.0f, 30.0f};
  s.sun.intensity = 0.8f;
  const Eigen::Vector3f lights[] = {{-10, 0, 3.5f}, {10, 0, 3.5f}, {0, 10, 3.5f}, {0, -11, 3.5f},
                                    {0, 0, 13.5f},  {0, 0, -3.5f}, {0, 7, 2}};
  for (const auto& p : lights) {
    s.point_lights.push_back(
        {p, Eigen::Vector3f(rng.uniform(0.4, 1), rng.uniform(0.4, 1), rng.uniform(0.4, 1)),
         static_cast<float>(rng.uniform(5, 50)), 0.1f, rng.bernoulli(0.8)});
  }
  s.environment = scene::Environment{};
  s.environment->color = {0.2f, 0.22f, 0.28f};
  s.post.exposure_ev = 0.3f;
  s.post.contrast = 10;
  s.post.saturation = -10;
  s.post.vignette = 0.3f;
  s.post.film_grain = 0.2f;
  return s;
}

const scene::Scene& cached_scene() {
  static const scene::Scene s = paper_scene();
  return s;
}

void BM_RayThroughput(benchmark::State& state) {
  render::Renderer r(cached_scene());
  long long rays = 0;
  double seconds = 0;
  for (auto _ : state) {
    r.render({.spp = 1, .post = false});
    rays += r.timings().rays;
    seconds += (r.timings().trace_ms + r.timings().shade_ms) / 1000.0;
  }
  state.counters["Mrays/s"] = rays / seconds / 1e6;
  state.counters["rays/frame"] =
      static_cast<double>(rays) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_RayThroughput)->Unit(benchmark::kMillisecond)->UseRealTime();

// The frame benchmarks' arguments: samples per pixel, light samples per pixel (decoupled
// shading; = spp is brute force), adaptive anti-aliasing (1 = on, the default; 0 = every pixel
// takes every sample).
render::RenderOptions frame_options(const benchmark::State& state) {
  render::RenderOptions options;
  options.spp = static_cast<int>(state.range(0));
  options.light_samples = static_cast<int>(state.range(1));
  if (!state.range(2)) options.adaptive_contrast = -1.0f;
  return options;
}

// Whole frame: build, trace, shade, edge marking, denoise, post, PNG encoding of all five
// buffers.
void run_paper_frame(benchmark::State& state, const scene::Scene& scene) {
  const render::RenderOptions options = frame_options(state);
  double refined = 0;
  double build = 0, trace = 0, shade = 0, edges = 0, denoise = 0, post = 0, encode = 0, render = 0;
  long long rays = 0;
  std::size_t triangles = 0;
  for (const auto& in : scene.instances) triangles += scene.meshes[in.mesh].triangles.size();
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    render::Renderer r(scene);
    const render::FrameBuffers f = r.render(options);
    render +=
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    const auto t0 = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(render::encode_frame(f));  // the five PNGs, in parallel
    encode +=
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    build += r.build_ms();
    trace += r.timings().trace_ms;
    shade += r.timings().shade_ms;
    edges += r.timings().edges_ms;
    denoise += r.timings().denoise_ms;
    post += r.timings().post_ms;
    rays += r.timings().rays;
    refined += r.timings().refined_fraction;
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["build_ms"] = build / n;
  state.counters["trace_ms"] = trace / n;
  state.counters["shade_ms"] = shade / n;
  state.counters["edges_ms"] = edges / n;
  state.counters["denoise_ms"] = denoise / n;
  state.counters["post_ms"] = post / n;
  state.counters["render_ms"] = render / n;  // everything but the encoding
  state.counters["encode_ms"] = encode / n;
  state.counters["Mrays/s"] = static_cast<double>(rays) / ((trace + shade) / 1000.0) / 1e6;
  state.counters["triangles"] = static_cast<double>(triangles);
  state.counters["refined"] = refined / n;  // fraction of pixels that took every sample
}
void BM_PaperFrame(benchmark::State& state) { run_paper_frame(state, cached_scene()); }
BENCHMARK(BM_PaperFrame)
    ->Args({1, 1, 1})
    ->Args({4, 1, 1})
    ->Args({4, 1, 0})
    ->Args({4, 4, 0})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The same frame with every light removed (no sun, point lights or sky): what a frame costs
// before any light is sampled or any shadow ray traced (build, primary rays, surfaces and
// textures, edge marking, denoise, post). BM_PaperFrame minus this is the price of the lighting.
void BM_PaperFrameUnlit(benchmark::State& state) {
  static const scene::Scene unlit = [] {
    scene::Scene s = cached_scene();
    s.sun.enabled = false;
    s.point_lights.clear();
    s.environment.reset();
    return s;
  }();
  run_paper_frame(state, unlit);
}
BENCHMARK(BM_PaperFrameUnlit)
    ->Args({1, 1, 1})
    ->Args({4, 1, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// Error of the frame against a reference (64 samples per pixel, each one lit, no smoothing;
// rendered once, ≈ 20 s): RMSE of the linear colour relative to the reference's mean, per pixel
// and over 9×9 means (the low-frequency mottling smoothing leaves). A change that trades rays
// against noise shows both sides: BM_PaperFrame gives the time, this the error. Arguments as
// BM_PaperFrame's.
void BM_PaperFrameError(benchmark::State& state) {
  static const cv::Mat reference =
      render::Renderer(cached_scene())
          .render({.spp = 64, .light_samples = 64, .denoise_radius = 0, .post = false})
          .linear;
  render::RenderOptions options = frame_options(state);
  options.post = false;
  render::Renderer r(cached_scene());
  cv::Mat frame;
  for (auto _ : state) frame = r.render(options).linear;
  const cv::Scalar ref_mean = cv::mean(reference);
  auto relative_rmse = [&](const cv::Mat& a, const cv::Mat& b) {
    const double rmse = cv::norm(a, b, cv::NORM_L2) / std::sqrt(static_cast<double>(a.total() * 3));
    return rmse / ((ref_mean[0] + ref_mean[1] + ref_mean[2]) / 3.0);
  };
  cv::Mat frame_9, reference_9;
  cv::blur(frame, frame_9, cv::Size(9, 9));
  cv::blur(reference, reference_9, cv::Size(9, 9));
  state.counters["rel_rmse"] = relative_rmse(frame, reference);
  state.counters["rel_rmse_9x9"] = relative_rmse(frame_9, reference_9);
}
BENCHMARK(BM_PaperFrameError)
    ->Args({1, 1, 1})
    ->Args({4, 1, 1})
    ->Args({4, 4, 0})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// A 1280×720 guide of four surfaces (quadrants) at two depths and two slants.
std::vector<render::LightingGuide> quadrant_guide(int w, int h) {
  std::vector<render::LightingGuide> guide(static_cast<std::size_t>(w) * h);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const int quadrant = (x >= w / 2) + 2 * (y >= h / 2);
      const float slant = quadrant % 2 ? 0.5f : 0.0f;
      render::LightingGuide& g = guide[static_cast<std::size_t>(y) * w + x];
      g.surface = quadrant;
      g.normal[0] = slant;
      g.normal[2] = std::sqrt(1 - slant * slant);
      g.position[0] = 0.005f * x;
      g.position[1] = -0.005f * y;
      g.position[2] = -2.0f - quadrant - slant * 0.005f * x;
    }
  }
  return guide;
}

// The lighting smoothing alone on the quadrant guide, noisy light.
void BM_Denoise(benchmark::State& state) {
  const int w = 1280, h = 720, radius = static_cast<int>(state.range(0));
  const std::vector<render::LightingGuide> guide = quadrant_guide(w, h);
  std::vector<render::PixelLight> noisy(guide.size());
  RandomStream rng(3, {"bench", "denoise"});
  for (auto& l : noisy) {
    for (int c = 0; c < 3; ++c) {
      l.diffuse[c] = static_cast<float>(rng.uniform(0, 2));
      l.specular[c] = static_cast<float>(rng.uniform(0, 0.1));
    }
  }
  render::DenoiseScratch scratch;
  std::vector<render::PixelLight> light;
  for (auto _ : state) {
    state.PauseTiming();
    light = noisy;
    state.ResumeTiming();
    render::denoise_lighting(w, h, guide, radius, light, &scratch);
    benchmark::DoNotOptimize(light.data());
  }
}
BENCHMARK(BM_Denoise)->Arg(3)->Unit(benchmark::kMillisecond)->UseRealTime();

// Edge marking of adaptive anti-aliasing alone, from guide planes as the renderer passes them:
// the quadrant guide with colour noise of which about one pixel pair in twelve crosses the
// contrast.
void BM_MarkEdges(benchmark::State& state) {
  const int w = 1280, h = 720;
  render::GuidePlanes planes;
  planes.assign(quadrant_guide(w, h));
  std::vector<float> color[3];
  RandomStream rng(4, {"bench", "edges"});
  for (auto& plane : color) {
    plane.resize(planes.size());
    for (float& c : plane) c = static_cast<float>(rng.uniform(0.4, 0.46));
  }
  std::vector<std::uint8_t> refine;
  for (auto _ : state) {
    render::mark_edges(w, h, planes, color, render::RenderOptions{}.adaptive_contrast, refine);
    benchmark::DoNotOptimize(refine.data());
  }
}
BENCHMARK(BM_MarkEdges)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
