// Motion pipeline throughput: 200 clips x 150 frames (issue target: < 2 s on 2 cores for the
// whole conversion). Run: build/release/bench/bench_motion

#include <benchmark/benchmark.h>

#include <filesystem>

#include "motion/batch.h"
#include "motion/test_support.h"

namespace {

using namespace wheelpose::motion;

std::vector<PositionClip> make_clips(int count, int frames) {
  std::vector<PositionClip> clips;
  for (int i = 0; i < count; ++i) {
    PositionClip clip = testing::synthetic_clip(frames, 20, i, 0.3);
    clip.name = "clip_" + std::to_string(i);
    clips.push_back(std::move(clip));
  }
  return clips;
}

void BM_PipelineOnly(benchmark::State& state) {
  const auto clips = make_clips(200, 150);
  for (auto _ : state) {
    for (const PositionClip& clip : clips) {
      benchmark::DoNotOptimize(run_motion_pipeline(clip, MotionOptions{}));
    }
  }
  state.SetItemsProcessed(state.iterations() * clips.size());
}
BENCHMARK(BM_PipelineOnly)->Unit(benchmark::kMillisecond);

void BM_ConvertBatchWithExports(benchmark::State& state) {
  const auto clips = make_clips(200, 150);
  const auto out = std::filesystem::temp_directory_path() / "wheelpose_bench_motion";
  const auto exporters = parse_exporter_list(state.range(0) ? "json,glb,bvh" : "json");
  for (auto _ : state) {
    auto result = convert_batch(
        clips.size(), [&](std::size_t i) { return clips[i]; }, MotionOptions{}, exporters, out);
    benchmark::DoNotOptimize(result);
  }
  std::filesystem::remove_all(out);
  state.SetItemsProcessed(state.iterations() * clips.size());
}
BENCHMARK(BM_ConvertBatchWithExports)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
