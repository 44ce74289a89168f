// `wheelpose generate` throughput and memory.
//   BM_GeneratePaperPreset: the paper preset (1280x720, 4 spp, 5-12 people, JPEG, all labels)
//     over 24 frames on every core (start-up included); counter images_per_s.
//   BM_GeneratePeakRss/N: N frames at 320x180, 1 spp; counter peak_rss_mb (VmHWM of the run,
//     reset before it; registered first so no larger frame's buffers are resident yet; a flat
//     figure means memory does not grow with the frame count).
//   BM_GenerateRealistic/{0,…,5}: 48 frames of the realistic scenario side by side — 0 before
//     the photo-real changes (its photo-real block cut: coloured lights, paper textures, hue
//     rotation; no bounce), 1 configs/boost-realistic.yaml without its bounce (black-body lights,
//     interior rooms), 2 configs/boost-realistic-train.yaml (also the phone camera), 3
//     configs/boost-realistic.yaml as it is (one diffuse bounce, hair as strands), 4 the same with
//     the hair as opaque cards (hair_strand_coverage: 1), 5 boost-realistic-train.yaml with the
//     shutter closed (PhoneCamera.shutter: 0, no motion blur; 2 against 5 is the blur's cost:
//     each person in a clip built twice, the streak buffer and the filter), 6 boost-realistic.yaml
//     before framing (the camera by an end wall, drawn once: 3 against 6 is framing's cost);
//     counters ms_per_image and, per
//     stage, the thread time per frame (draft_ms, build_ms, bvh_ms, render_ms, label_ms,
//     write_ms).
// Run: build/release/bench/bench_generate

#include <benchmark/benchmark.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "core/config.h"
#include "generate/runner.h"
#include "generate/scenario.h"

namespace {

namespace fs = std::filesystem;

double peak_rss_mb() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmHWM:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  }
  return 0;
}

wheelpose::generate::RunOptions options(const std::string& name, std::int64_t frames) {
  wheelpose::generate::RunOptions o;
  o.out = fs::temp_directory_path() / ("wheelpose_bench_" + name);
  fs::remove_all(o.out);
  o.frames = frames;
  o.seed = 1;
  o.assets = fs::path(WHEELPOSE_SHARED_DIR) / "assets";
  return o;
}

void BM_GeneratePeakRss(benchmark::State& state) {
  const auto scenario = wheelpose::generate::Scenario::from_config(
      wheelpose::ConfigNode::load_string("image: {width: 320, height: 180, spp: 1}\n", "<bench>"));
  for (auto _ : state) {
    // Reset the high-water mark so each run reports its own peak (Linux ≥ 4.0).
    std::ofstream("/proc/self/clear_refs") << "5";
    const auto o = options("rss", state.range(0));
    const auto summary = wheelpose::generate::run_generate(scenario, o);
    state.SetIterationTime(summary.seconds);
    state.counters["images_per_s"] = static_cast<double>(summary.rendered) / summary.seconds;
    state.counters["peak_rss_mb"] = peak_rss_mb();
    fs::remove_all(o.out);
  }
}
BENCHMARK(BM_GeneratePeakRss)
    ->Arg(200)
    ->Arg(2000)
    ->Iterations(1)
    ->UseManualTime()
    ->Unit(benchmark::kSecond);

void BM_GeneratePaperPreset(benchmark::State& state) {
  const auto scenario = wheelpose::generate::Scenario::defaults();
  for (auto _ : state) {
    const auto o = options("paper", state.range(0));
    const auto summary = wheelpose::generate::run_generate(scenario, o);
    state.SetIterationTime(summary.seconds);
    state.counters["images_per_s"] = static_cast<double>(summary.rendered) / summary.seconds;
    state.counters["people_per_image"] =
        static_cast<double>(summary.annotations) / static_cast<double>(summary.images);
    fs::remove_all(o.out);
  }
}
// The realistic scenario as the benchmark argument chooses (see the top of the file).
wheelpose::generate::Scenario realistic_scenario(std::int64_t which) {
  const fs::path configs = fs::path(WHEELPOSE_SOURCE_DIR) / "configs";
  const fs::path file =
      configs / (which == 2 || which == 5 ? "boost-realistic-train.yaml" : "boost-realistic.yaml");
  std::ostringstream text;
  text << std::ifstream(file).rdbuf();
  std::string yaml = text.str();
  if (which == 0 || which == 6) {  // the camera as before framing
    const std::string walls = "    room_walls: all\n";
    yaml.erase(yaml.find(walls), walls.size());
    yaml = yaml.substr(0, yaml.find("\nframing:") + 1);
  }
  if (which == 0) yaml = yaml.substr(0, yaml.find("  # Photo-real light"));
  if (which == 5) {
    const std::string phone = "  PhoneCamera:\n";
    yaml.insert(yaml.find(phone) + phone.size(), "    shutter: 0\n");
  }
  if (which == 4) {
    const std::string people = "  HumanGeneration:\n";
    yaml.insert(yaml.find(people) + people.size(), "    hair_strand_coverage: 1\n");
  }
  auto scenario = wheelpose::generate::Scenario::from_config(
      wheelpose::ConfigNode::load_string(yaml, file.string()));
  if (which <= 1) scenario.bounce = false;  // the scenario before the bounce
  return scenario;
}

void BM_GenerateRealistic(benchmark::State& state) {
  const auto scenario = realistic_scenario(state.range(0));
  for (auto _ : state) {
    auto o = options("realistic", 48);
    o.motions.clips_from =
        (fs::path(WHEELPOSE_SOURCE_DIR) / "configs" / "boost-test-clips.json").string();
    const auto summary = wheelpose::generate::run_generate(scenario, o);
    state.SetIterationTime(summary.seconds);
    state.counters["ms_per_image"] =
        1000.0 * summary.seconds / static_cast<double>(summary.rendered);
    // Per stage, thread time per frame (the stages of 2 threads add up to ~2 × ms_per_image).
    state.counters["draft_ms"] = summary.stage_ms.draft;
    state.counters["build_ms"] = summary.stage_ms.build;
    state.counters["bvh_ms"] = summary.stage_ms.bvh;
    state.counters["render_ms"] = summary.stage_ms.render;
    state.counters["label_ms"] = summary.stage_ms.label;
    state.counters["write_ms"] = summary.stage_ms.write;
    fs::remove_all(o.out);
  }
}
BENCHMARK(BM_GenerateRealistic)
    ->Arg(0)
    ->Arg(1)
    ->Arg(2)
    ->Arg(3)
    ->Arg(4)
    ->Arg(5)
    ->Arg(6)
    ->Iterations(1)
    ->UseManualTime()
    ->Unit(benchmark::kSecond);

BENCHMARK(BM_GeneratePaperPreset)
    ->Arg(24)
    ->Iterations(1)
    ->UseManualTime()
    ->Unit(benchmark::kSecond);

}  // namespace
