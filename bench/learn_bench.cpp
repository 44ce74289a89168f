// MoveNet inference through LibTorch (learn::PosePredictor), per model and input size, on the
// COCO sample image scaled to 1280×720 (a generated frame's size). scripts/bench_movenet.sh
// runs this beside TF.js (wasm) on the same network inputs, which `bench_learn
// --write-tfjs-inputs DIR` writes as PNGs with a manifest for tests/tfjs_reference. Threads: all
// cores unless WHEELPOSE_BENCH_THREADS says otherwise.

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/allocator.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "learn/letterbox.h"
#include "learn/model_files.h"
#include "learn/pose_predictor.h"
#include "learn/train_data.h"
#include "learn/train_probe.h"

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

// size 0: predict's default, the 256 and 640 inputs merged.
std::unique_ptr<PosePredictor> load(const std::string& name, int size) {
  const fs::path model = wheelpose::learn::resolve_model(name, std::nullopt);
  wheelpose::learn::PredictOptions options{.threads = bench_threads()};
  if (size > 0) options.longer_sides = {size};
  return std::make_unique<PosePredictor>(model, options);
}

constexpr int kMultiposeSizes[] = {256, 384, 512, 640};
const wheelpose::coco::Box kPersonBox = {440, 160, 400, 400};

void BM_Multipose(benchmark::State& state) {
  const auto predictor = load("movenet-multipose", static_cast<int>(state.range(0)));
  const cv::Mat rgb = frame();
  for (auto _ : state) benchmark::DoNotOptimize(predictor->predict_image(rgb));
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_Multipose)
    ->Arg(kMultiposeSizes[0])
    ->Arg(kMultiposeSizes[1])
    ->Arg(kMultiposeSizes[2])
    ->Arg(kMultiposeSizes[3])
    ->Arg(0)  // the default: 256 and 640 merged
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// One person crop per iteration, the box the middle of the frame.
void BM_SinglePerson(benchmark::State& state, const char* name) {
  const auto predictor = load(name, 256);
  const cv::Mat rgb = frame();
  const std::vector<wheelpose::coco::Box> box = {kPersonBox};
  for (auto _ : state) benchmark::DoNotOptimize(predictor->predict_boxes(rgb, box));
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK_CAPTURE(BM_SinglePerson, lightning, "movenet-lightning")
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_SinglePerson, thunder, "movenet-thunder")
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The network inputs the benchmarks above build, as PNGs named like the benchmarks, and a
// manifest that tests/tfjs_reference/reference.mjs reads.
void write_tfjs_inputs(const fs::path& dir) {
  fs::create_directories(dir);
  nlohmann::json manifest = {{"inputs", nlohmann::json::array()}};
  auto write = [&](const std::string& file, const std::string& model, const cv::Mat& rgb) {
    cv::Mat bgr;
    cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
    if (!cv::imwrite((dir / file).string(), bgr)) {
      throw wheelpose::Error("cannot write " + (dir / file).string());
    }
    manifest["inputs"].push_back({{"file", file}, {"model", model}});
  };
  const cv::Mat rgb = frame();
  for (const int size : kMultiposeSizes) {
    write("BM_Multipose_" + std::to_string(size) + ".png", "movenet-multipose",
          wheelpose::learn::letterbox_image(
              rgb, wheelpose::learn::plan_letterbox(rgb.cols, rgb.rows, size)));
  }
  const auto crop = wheelpose::learn::square_around(kPersonBox);
  write("BM_SinglePerson_lightning.png", "movenet-lightning",
        wheelpose::learn::crop_image(rgb, crop, 192));
  write("BM_SinglePerson_thunder.png", "movenet-thunder",
        wheelpose::learn::crop_image(rgb, crop, 256));
  wheelpose::write_file_atomic(dir / "manifest.json", manifest.dump(2) + "\n");
}

// Training throughput as `train` runs it (batch 16 at 256², augmented crops of the COCO
// sample's people, data loading excluded): channels-last convolutions (what train uses) against
// NCHW. Items are images, so items_per_second is images/s.
void BM_TrainStep(benchmark::State& state) {
  const bool channels_last = state.range(0) != 0;
  const fs::path sample = fs::path(WHEELPOSE_SHARED_DIR) / "data" / "coco-sample";
  const wheelpose::coco::CocoGroundTruth gt =
      wheelpose::coco::load_coco_gt(sample / "person_keypoints_sample.json", 17, false);
  std::vector<wheelpose::learn::TrainPerson> people;  // those of the one image shipped
  for (const wheelpose::coco::GtAnnotation& a : gt.annotations) {
    if (a.image_id != 785 || a.iscrowd || a.keypoints.size() != 51) continue;
    wheelpose::learn::TrainPerson person;
    person.box = a.bbox;
    std::copy(a.keypoints.begin(), a.keypoints.end(), person.keypoints.begin());
    people.push_back(person);
  }
  cv::Mat rgb;
  cv::cvtColor(cv::imread((sample / "000000000785.jpg").string()), rgb, cv::COLOR_BGR2RGB);
  constexpr int kBatch = 16, kSize = 256;
  wheelpose::learn::AugmentOptions augment;
  augment.input_size = kSize;
  std::vector<wheelpose::learn::TrainSample> samples;
  for (int i = 0; i < kBatch; ++i) {
    samples.push_back(wheelpose::learn::augment(rgb, people, {}, augment, 1, i));
  }
  const fs::path model = wheelpose::learn::resolve_model("movenet-multipose", std::nullopt);
  wheelpose::learn::TrainStepProbe probe(model, samples, kSize, channels_last, bench_threads());
  probe.step();  // the first step allocates the optimizer state
  for (auto _ : state) benchmark::DoNotOptimize(probe.step());
  state.SetItemsProcessed(state.iterations() * kBatch);
}
BENCHMARK(BM_TrainStep)
    ->ArgName("channels_last")
    ->Arg(1)
    ->Arg(0)
    ->Unit(benchmark::kMillisecond)
    ->MinTime(10)
    ->UseRealTime();

}  // namespace

// Heap tuning as `wheelpose predict` does it (core/allocator.h).
int main(int argc, char** argv) {
  if (argc == 3 && std::strcmp(argv[1], "--write-tfjs-inputs") == 0) {
    try {
      write_tfjs_inputs(argv[2]);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "error: %s\n", e.what());
      return 1;
    }
    return 0;
  }
  wheelpose::retain_freed_memory();
  wheelpose::retain_large_blocks();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
