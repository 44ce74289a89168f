// `wheelpose render SCENE.json --out DIR`: renders a scene dumped as JSON into rgb, depth,
// normals, instance and semantic PNGs (a debug and test entry point for the renderer).

#include <spdlog/spdlog.h>
#include <tbb/global_control.h>

#include <CLI/CLI.hpp>
#include <memory>
#include <optional>
#include <string>
#include <thread>

#include "core/error.h"
#include "render/frame_io.h"
#include "render/renderer.h"
#include "scene/scene_json.h"

namespace wheelpose::app {
namespace {

struct RenderCommandOptions {
  std::string scene;
  std::string out;
  render::RenderOptions render;  // spp 1 unless --spp; post off with --no-post
  int threads = 0;
  bool no_post = false;
  std::optional<std::uint64_t> seed;
};

void run_render(const RenderCommandOptions& o) {
  render::RenderOptions options = o.render;
  options.post = !o.no_post;
  options.check({"--spp", "--light-samples", "--denoise", "--adaptive-contrast"});
  std::optional<tbb::global_control> limit;
  if (o.threads > 0) limit.emplace(tbb::global_control::max_allowed_parallelism, o.threads);
  scene::Scene s = scene::load_scene(o.scene);
  if (o.seed) s.seed = *o.seed;
  std::unique_ptr<render::Renderer> renderer;
  try {
    renderer = std::make_unique<render::Renderer>(s);
  } catch (const Error& e) {
    // Texture errors name the JSON entry; add the file they belong to.
    throw Error(o.scene + ": " + e.what(), e.kind());
  }
  const render::FrameBuffers frame = renderer->render(options);
  const render::WriteTimings w = render::write_frame(frame, o.out);
  const auto& t = renderer->timings();
  spdlog::info(
      "rendered {}x{} at {} spp ({} lit, {:.1f} % of pixels took all): build {:.1f} ms, trace "
      "{:.1f} ms, shade {:.1f} ms, edges {:.1f} ms, denoise {:.1f} ms, post {:.1f} ms, encode "
      "{:.1f} ms, write {:.1f} ms ({} rays) -> {}",
      s.camera.width, s.camera.height, options.spp, options.light_samples,
      100.0 * t.refined_fraction, renderer->build_ms(), t.trace_ms, t.shade_ms, t.edges_ms,
      t.denoise_ms, t.post_ms, w.encode_ms, w.write_ms, t.rays, o.out);
}

}  // namespace

void attach_render(CLI::App& parent) {
  auto options = std::make_shared<RenderCommandOptions>();
  CLI::App* cmd = parent.add_subcommand(
      "render", "Render a scene JSON into rgb/depth/normals/instance/semantic PNGs");
  cmd->add_option("SCENE", options->scene, "Scene JSON file")->required();
  cmd->add_option("--out", options->out, "Output directory (created if needed)")->required();
  // Their ranges are checked by RenderOptions::check.
  cmd->add_option("--spp", options->render.spp, "Samples per pixel (1 to 4096)");
  cmd->add_option("--light-samples", options->render.light_samples,
                  "Samples per pixel that also sample the lights (1 to --spp; the others reuse "
                  "the pixel's lighting)");
  cmd->add_option("--denoise", options->render.denoise_radius,
                  "Lighting smoothing radius in pixels (0 = off, at most 16)");
  cmd->add_option("--adaptive-contrast", options->render.adaptive_contrast,
                  "Adaptive anti-aliasing: only pixels at an edge (another surface, a crease, a "
                  "depth step, an albedo step above this) take every sample; negative = all "
                  "pixels do (-1 to 1)");
  cmd->add_flag("--bounce", options->render.bounce,
                "One diffuse bounce of the sun and point lights (fills shadows; slower)");
  cmd->add_option("--threads", options->threads, "Worker threads (0 = all cores)")
      ->check(CLI::Range(0, 1024));
  cmd->add_option("--seed", options->seed, "Override the scene's sampling seed");
  cmd->add_flag("--no-post", options->no_post, "Skip post-processing (plain sRGB encoding)");
  cmd->callback([options] { run_render(*options); });
}

}  // namespace wheelpose::app
