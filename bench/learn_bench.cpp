// MoveNet inference through LibTorch (learn::PosePredictor), per model and input size, on the
// COCO sample image scaled to 1280×720 (a generated frame's size). scripts/bench_movenet.sh
// runs this beside TF.js (wasm) on the same inputs. Threads: all cores unless
// WHEELPOSE_BENCH_THREADS says otherwise.

#include <benchmark/benchmark.h>

#include <cstdlib>
#include <filesystem>
#include <memory>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "learn/model_files.h"
#include "learn/pose_predictor.h"

namespace {

namespace fs = std::filesystem;
using wheelpose::learn::PosePredictor;

int bench_threads() {
  const char* env = std::getenv("WHEELPOSE_BENCH_THREADS");
  return env ? std::atoi(env) : 0;
}

cv::Mat frame() {
  static const cv::Mat rgb = [] {
    const cv::Mat bgr = cv::imread(
        (fs::path(WHEELPOSE_SHARED_DIR) / "data" / "coco-sample" / "000000000785.jpg").string());
    cv::Mat resized, out;
    cv::resize(bgr, resized, cv::Size(1280, 720));
    cv::cvtColor(resized, out, cv::COLOR_BGR2RGB);
    return out;
  }();
  return rgb;
}

std::unique_ptr<PosePredictor> load(const std::string& name, int size) {
  const fs::path model = wheelpose::learn::resolve_model(name, std::nullopt);
  return std::make_unique<PosePredictor>(
      model, wheelpose::learn::PredictOptions{.longer_side = size, .threads = bench_threads()});
}

void BM_Multipose(benchmark::State& state) {
  const auto predictor = load("movenet-multipose", static_cast<int>(state.range(0)));
  const cv::Mat rgb = frame();
  for (auto _ : state) benchmark::DoNotOptimize(predictor->predict_image(rgb));
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_Multipose)
    ->Arg(256)
    ->Arg(384)
    ->Arg(512)
    ->Arg(640)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// One person crop per iteration, the box the middle of the frame.
void BM_SinglePerson(benchmark::State& state, const char* name) {
  const auto predictor = load(name, 256);
  const cv::Mat rgb = frame();
  const std::vector<wheelpose::eval::Box> box = {{440, 160, 400, 400}};
  for (auto _ : state) benchmark::DoNotOptimize(predictor->predict_boxes(rgb, box));
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK_CAPTURE(BM_SinglePerson, lightning, "movenet-lightning")
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_SinglePerson, thunder, "movenet-thunder")
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
