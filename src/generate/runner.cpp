// The generation run: sharding, parallel frames, per-frame fragments, resume, assembly.

#include "generate/runner.h"

#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <memory>
#include <mutex>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string_view>

#include "body/assets.h"
#include "body/person.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "dataset/coco_file.h"
#include "generate/frame_builder.h"
#include "generate/framing.h"
#include "generate/labeler.h"
#include "render/frame_io.h"
#include "render/renderer.h"

namespace wheelpose::generate {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;
using ordered_json = nlohmann::ordered_json;

// Everything that decides the output bytes; resuming into a folder written with other settings
// would mix two datasets.
ordered_json provenance(const Scenario& scenario, const RunOptions& options,
                        const std::vector<motion::SeatedClip>& clips) {
  ordered_json j;
  j["format"] = "wheelpose.scenario";
  j["version"] = 1;
  j["seed"] = options.seed;
  j["frames"] = options.frames;
  j["image_format"] = options.format;
  j["scenario"] = scenario.to_json();
  ordered_json names = ordered_json::array();
  for (const auto& c : clips) names.push_back(c.motion.name);
  j["motions"] = std::move(names);
  return j;
}

// The image shrunk by `factor` (area filter) and enlarged back (bilinear): the detail a small or
// digitally zoomed photo lacks. Pixel positions, and so labels, are unchanged.
cv::Mat resampled(const cv::Mat& rgb, float factor) {
  if (factor >= 1.0f) return rgb;
  cv::Mat small, back;
  const cv::Size reduced(std::max(1, static_cast<int>(std::lround(rgb.cols * factor))),
                         std::max(1, static_cast<int>(std::lround(rgb.rows * factor))));
  cv::resize(rgb, small, reduced, 0, 0, cv::INTER_AREA);
  cv::resize(small, back, rgb.size(), 0, 0, cv::INTER_LINEAR);
  return back;
}

std::vector<std::uint8_t> encode_image(const cv::Mat& rgb, const std::string& format, int quality) {
  cv::Mat bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  std::vector<std::uint8_t> bytes;
  std::vector<int> params;
  // OpenCV 4.6 leaves chroma subsampling at libjpeg's default, 4:2:0, as phones write it
  // (PhotorealCli checks the frame header).
  if (format == "jpg") params = {cv::IMWRITE_JPEG_QUALITY, quality, cv::IMWRITE_JPEG_OPTIMIZE, 0};
  if (!cv::imencode("." + format, bgr, bytes, params)) throw Error("cannot encode " + format);
  return bytes;
}

// annotations.json in the canonical form of dataset::write_coco, streamed from the fragments so
// memory does not grow with the frame count.
std::pair<std::int64_t, std::int64_t> assemble_annotations(const fs::path& out, std::int64_t first,
                                                           std::int64_t end, const json& info,
                                                           const json& cat) {
  AtomicFileWriter file(out / "annotations.json");
  auto fragment = [&](std::int64_t frame) {
    const fs::path path = out / "labels" / (frame_stem(frame) + ".json");
    try {
      return json::parse(read_file(path));
    } catch (const json::parse_error& e) {
      throw Error(path.string() +
                  ": malformed label fragment (delete it and re-run with --resume): " + e.what());
    }
  };
  dataset::CanonicalCocoWriter coco([&file](const std::string& text) { file.write(text); });
  std::int64_t annotations = 0;
  coco.begin_array("annotations");
  for (std::int64_t f = first; f < end; ++f) {
    json frag = fragment(f);
    for (json& a : frag["annotations"]) {
      a["id"] = ++annotations;
      a["image_id"] = f + 1;
      coco.element(a);
    }
  }
  coco.end_array();
  coco.member("categories", json::array({cat}));
  coco.begin_array("images");
  for (std::int64_t f = first; f < end; ++f) {
    json image = fragment(f)["image"];
    image["id"] = f + 1;
    coco.element(image);
  }
  coco.end_array();
  coco.member("info", info);
  coco.member("licenses", json::array());
  coco.finish();
  file.commit();
  return {end - first, annotations};
}

}  // namespace

std::string frame_stem(std::int64_t frame) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%06lld", static_cast<long long>(frame));
  return buffer;
}

void RunOptions::check() const {
  if (frames < 1) throw Error("--frames must be at least 1");
  if (shard_count < 1 || shard_index < 0 || shard_index >= shard_count)
    throw Error("--shard: expected i/N with 0 <= i < N");
  if (format != "jpg" && format != "png") throw Error("--format: expected jpg or png");
  if (out.empty()) throw Error("--out is required");
  if (threads < 0) throw Error("--threads must be 0 (every core) or more");
}

std::pair<std::int64_t, std::int64_t> shard_range(std::int64_t frames, int index, int count) {
  return {frames * index / count, frames * (index + 1) / count};
}

RunSummary run_generate(const Scenario& scenario, const RunOptions& options,
                        const ProgressFn& progress) {
  const auto start = std::chrono::steady_clock::now();
  options.check();

  std::optional<tbb::global_control> threads;
  if (options.threads > 0)
    threads.emplace(tbb::global_control::max_allowed_parallelism,
                    static_cast<std::size_t>(options.threads));

  const std::vector<motion::SeatedClip> clips = load_motion_clips(options.motions);
  const std::filesystem::path assets = body::locate_assets(options.assets);
  const body::BodyData body_data(assets);
  const FurnitureCatalog furniture(FurnitureCatalog::default_archive(),
                                   FurnitureCatalog::default_clothes_archive());

  const fs::path out = options.out;
  ensure_directory(out / "images");
  ensure_directory(out / "labels");
  if (scenario.ground_truth_maps) ensure_directory(out / "maps");
  for (const char* sub : {"", "images", "labels", "maps"}) remove_stale_temporaries(out / sub);

  ordered_json record = provenance(scenario, options, clips);
  record["furniture"] = {{"archive", furniture.archive().string()},
                         {"models", furniture.furniture_count()}};
  // Recorded only when drawn, so the records of runs without them read back the same.
  if (std::any_of(scenario.randomizers.begin(), scenario.randomizers.end(),
                  [](const Scenario::Active& a) {
                    return std::string_view(a.entry->name) == "HangingClothes";
                  })) {
    record["hanging_clothes"] = {{"archive", FurnitureCatalog::default_clothes_archive().string()},
                                 {"models", furniture.hanging_clothes().size()}};
  }
  const body::ProxyCatalog proxies = body::ProxyCatalog::scan(assets / "makehuman");
  record["proxies"] = {{"clothes", proxies.male_suits.size() + proxies.female_suits.size() +
                                       proxies.shoes.size() + proxies.hats.size()},
                       {"hair", proxies.hair.size()},
                       {"eyebrows", proxies.eyebrows.size()}};
  const std::string record_text = record.dump(2) + "\n";
  const fs::path record_path = out / "scenario.json";
  if (options.resume && fs::exists(record_path) && read_file(record_path) != record_text) {
    throw Error(record_path.string() +
                ": written by a run with other settings, seed, frame count or clips; resume with "
                "the same arguments or use a new --out");
  }
  write_file_atomic(record_path, record_text);

  RandomizerContext context;
  context.width = scenario.width;
  context.height = scenario.height;
  context.furniture_count = furniture.furniture_count();
  context.hanging_clothes = furniture.hanging_clothes();
  context.proxies = proxies;
  for (const auto& c : clips) {
    context.clip_names.push_back(c.motion.name);
    context.clip_durations.push_back(static_cast<double>(c.motion.frame_count()) / c.motion.fps);
  }

  RunSummary summary;
  std::tie(summary.first_frame, summary.end_frame) =
      shard_range(options.frames, options.shard_index, options.shard_count);
  std::vector<std::int64_t> pending;
  for (std::int64_t f = summary.first_frame; f < summary.end_frame; ++f) {
    if (options.resume && fs::exists(out / "labels" / (frame_stem(f) + ".json"))) {
      ++summary.resumed;
    } else {
      pending.push_back(f);
    }
  }
  const std::int64_t total = summary.end_frame - summary.first_frame;
  std::atomic<std::int64_t> done{summary.resumed}, dropped{0};
  std::mutex progress_mutex;
  if (progress) progress(done, total);

  const LabelOptions label_options{scenario.min_visible_pixels, scenario.segmentation,
                                   scenario.box_holds_wheelchair};
  enum Stage { kDraft, kBuild, kBvh, kRender, kLabel, kWrite, kStages };
  std::array<std::atomic<double>, kStages> stage_ms{};
  tbb::parallel_for(std::size_t{0}, pending.size(), std::size_t{1}, [&](std::size_t i) {
    auto stage_start = std::chrono::steady_clock::now();
    const auto stage_done = [&](Stage stage) {
      const auto now = std::chrono::steady_clock::now();
      stage_ms[stage] += std::chrono::duration<double, std::milli>(now - stage_start).count();
      stage_start = now;
    };
    const std::int64_t frame = pending[i];
    FrameDraft draft = draft_frame(scenario, options.seed, frame, context);
    stage_done(kDraft);
    BuiltFrame built = build_frame(draft, body_data, clips, scenario.anchors, &furniture);
    stage_done(kBuild);
    auto renderer = std::make_unique<render::Renderer>(built.scene);
    stage_done(kBvh);
    if (scenario.framing.attempts > 1) {
      // Framing's ray casts count as drafting; a rare second build as building.
      const int draw =
          choose_camera_draw(scenario, options.seed, frame, context, draft, built, *renderer);
      stage_done(kDraft);
      if (draw > 0) {
        FrameDraft redrawn = draft_frame(scenario, options.seed, frame, context, draw);
        if (leaves_out_the_same_objects(built, draft.camera.position, redrawn.camera.position)) {
          // Only the camera differs from the frame built: build_frame(redrawn) would give this.
          built.scene.camera = redrawn.camera;
          renderer->set_camera(redrawn.camera);
          draft = std::move(redrawn);
        } else {
          draft = std::move(redrawn);
          built = build_frame(draft, body_data, clips, scenario.anchors, &furniture);
          stage_done(kBuild);
          renderer = std::make_unique<render::Renderer>(built.scene);
          stage_done(kBvh);
        }
      }
      draft.image_attributes["camera_draws"] = draw + 1;
    }
    const render::FrameBuffers buffers = renderer->render(scenario.render_options());
    stage_done(kRender);
    FrameLabels labels = label_frame(built, buffers, label_options);
    dropped += labels.dropped_people;
    stage_done(kLabel);

    const std::string stem = frame_stem(frame);
    const std::string file_name = stem + "." + options.format;
    write_file_atomic(
        out / "images" / file_name,
        encode_image(resampled(buffers.rgb, draft.rescale), options.format,
                     draft.jpeg_quality > 0 ? draft.jpeg_quality : scenario.jpeg_quality));
    if (scenario.ground_truth_maps) {
      write_file_atomic(out / "maps" / (stem + "_depth.png"),
                        render::encode_png(render::depth_to_millimetres(buffers.depth)));
      write_file_atomic(out / "maps" / (stem + "_normals.png"),
                        render::encode_png(render::normals_to_u16(buffers.normals)));
      write_file_atomic(out / "maps" / (stem + "_instance.png"),
                        render::encode_png(buffers.instance));
      write_file_atomic(out / "maps" / (stem + "_semantic.png"),
                        render::encode_png(buffers.semantic));
    }
    ordered_json image;
    image["file_name"] = file_name;
    for (auto& [key, value] : labels.image.items()) image[key] = value;
    image["frame"] = frame;
    image["seed"] = options.seed;
    image["environment"] = draft.environment == EnvironmentKind::kWall ? "wall"
                           : draft.room.outdoor                        ? "outdoor"
                                                                       : "room";
    image["nominal_focal_length_mm"] = std::round(draft.nominal_focal_length_mm * 1e4) / 1e4;
    for (const auto& [key, value] : draft.image_attributes.items()) image[key] = value;
    ordered_json fragment;
    fragment["image"] = std::move(image);
    fragment["annotations"] = std::move(labels.annotations);
    // The fragment is written last: its presence means the frame is complete.
    write_file_atomic(out / "labels" / (stem + ".json"), fragment.dump() + "\n");
    stage_done(kWrite);
    const std::int64_t now = ++done;
    if (progress) {
      std::lock_guard<std::mutex> lock(progress_mutex);
      progress(now, total);
    }
  });
  summary.rendered = static_cast<std::int64_t>(pending.size());
  summary.dropped_people = dropped;
  const double per_frame = 1.0 / static_cast<double>(std::max<std::size_t>(1, pending.size()));
  summary.stage_ms = {stage_ms[kDraft] * per_frame, stage_ms[kBuild] * per_frame,
                      stage_ms[kBvh] * per_frame,   stage_ms[kRender] * per_frame,
                      stage_ms[kLabel] * per_frame, stage_ms[kWrite] * per_frame};

  json info = {{"description", "WheelPose synthetic wheelchair users"},
               {"version", "1"},
               {"seed", options.seed},
               {"frames", options.frames},
               {"scenario", "scenario.json"}};
  std::tie(summary.images, summary.annotations) =
      assemble_annotations(out, summary.first_frame, summary.end_frame, info,
                           coco_person_category(scenario.keypoint_template));
  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return summary;
}

}  // namespace wheelpose::generate
