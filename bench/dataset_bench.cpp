// `wheelpose coco validate` and `wheelpose stats` on a synthetic COCO file of 70,000 images and
// 300,000 people (with camera metadata and 3D keypoints, so every analysis runs).
// Run: build/<dir>/bench/bench_dataset [--write-only PATH]
// The file is written once to $TMPDIR/wheelpose_dataset_bench.json; time the CLI on it with
//   /usr/bin/time -v build/<dir>/wheelpose coco validate $TMPDIR/wheelpose_dataset_bench.json

#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>

#include "core/atomic_file.h"
#include "core/random.h"
#include "dataset/coco_file.h"
#include "dataset/stats.h"
#include "dataset/stats_report.h"

namespace {

namespace fs = std::filesystem;
using namespace wheelpose::dataset;

constexpr int kImages = 70000, kPeople = 300000;

void append(std::string& out, const char* format, double a) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, a);
  out += buf;
}

// Text written directly (a DOM of this size would double the generator's memory).
std::string synthetic_text() {
  std::string out =
      "{\"categories\":" +
      std::string(
          R"([{"id":1,"name":"person","supercategory":"person","keypoints":["nose","left_eye","right_eye","left_ear","right_ear","left_shoulder","right_shoulder","left_elbow","right_elbow","left_wrist","right_wrist","left_hip","right_hip","left_knee","right_knee","left_ankle","right_ankle"],"skeleton":[[16,14],[14,12],[17,15],[15,13],[12,13],[6,12],[7,13],[6,7],[6,8],[7,9],[8,10],[9,11],[2,3],[1,2],[1,3],[2,4],[3,5],[4,6],[5,7]]}])");
  out += ",\"images\":[";
  for (int i = 0; i < kImages; ++i) {
    wheelpose::RandomStream rng(11, {"dataset_bench_camera", i});
    out += (i ? ",{\"id\":" : "{\"id\":") + std::to_string(i + 1) + ",\"file_name\":\"" +
           std::to_string(i + 1) + ".png\",\"width\":1280,\"height\":720,\"motion_id\":\"clip" +
           std::to_string(i / 30) + "\",\"camera\":{\"extrinsics\":[1,0,0,";
    append(out, "%.3f", rng.uniform(-10, 10));
    out += ",0,1,0,";
    append(out, "%.3f", rng.uniform(1, 8));
    out += ",0,0,1,";
    append(out, "%.3f", rng.uniform(5, 25));
    out += ",0,0,0,1]}}";
  }
  out += "],\"annotations\":[";
  for (int a = 0; a < kPeople; ++a) {
    // People spread over images: image = a * kImages / kPeople (4-5 per image).
    const int image = static_cast<int>(static_cast<long long>(a) * kImages / kPeople) + 1;
    wheelpose::RandomStream rng(11, {"dataset_bench_person", a});
    const double w = rng.uniform(30, 300), h = rng.uniform(60, 500);
    const double x = rng.uniform(0, 1280 - w), y = rng.uniform(0, 720 - h);
    std::string kp, k3;
    int labelled = 0;
    for (int k = 0; k < 17; ++k) {
      const int v = static_cast<int>(rng.uniform_int(0, 2));
      labelled += v > 0;
      if (k) kp += ",";
      if (v == 0) {
        kp += "0,0,0";
      } else {
        append(kp, "%.2f", x + rng.uniform(0, w));
        kp += ",";
        append(kp, "%.2f", y + rng.uniform(0, h));
        kp += "," + std::to_string(v);
      }
      if (k) k3 += ",";
      append(k3, "%.3f", (k == 11 ? 0.1 : k == 12 ? -0.1 : 0.0) + rng.uniform(-0.02, 0.02));
      k3 += ",";
      append(k3, "%.3f", k == 0 ? 1.5 : 1.0);
      k3 += ",";
      append(k3, "%.3f", rng.uniform(-0.02, 0.02));
    }
    out += a ? ",{" : "{";
    out += "\"id\":" + std::to_string(a + 1) + ",\"image_id\":" + std::to_string(image) +
           ",\"category_id\":1,\"iscrowd\":0,\"bbox\":[";
    append(out, "%.2f", x);
    out += ",";
    append(out, "%.2f", y);
    out += ",";
    append(out, "%.2f", w);
    out += ",";
    append(out, "%.2f", h);
    out += "],\"area\":";
    append(out, "%.1f", w * h * 0.6);
    out += ",\"num_keypoints\":" + std::to_string(labelled) + ",\"keypoints\":[" + kp +
           "],\"keypoints_3d\":[" + k3 + "]}";
  }
  out += "]}\n";
  return out;
}

const fs::path& synthetic_file() {
  static const fs::path path = [] {
    const fs::path p = fs::temp_directory_path() / "wheelpose_dataset_bench.json";
    if (!fs::exists(p)) wheelpose::write_file_atomic(p, synthetic_text());
    return p;
  }();
  return path;
}

void BM_LoadJson(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(load_json(synthetic_file()));
}
BENCHMARK(BM_LoadJson)->Unit(benchmark::kSecond)->Iterations(1);

void BM_Validate(benchmark::State& state) {
  const json root = load_json(synthetic_file());
  for (auto _ : state) {
    const auto problems = validate_coco(root);
    if (!problems.empty()) state.SkipWithError(problems.front().message.c_str());
  }
}
BENCHMARK(BM_Validate)->Unit(benchmark::kSecond)->Iterations(1);

void BM_ComputeStats(benchmark::State& state) {
  const json root = load_json(synthetic_file());
  for (auto _ : state) benchmark::DoNotOptimize(compute_stats(root, "bench", "bench"));
}
BENCHMARK(BM_ComputeStats)->Unit(benchmark::kSecond)->Iterations(1);

void BM_StatsFigures(benchmark::State& state) {
  const json root = load_json(synthetic_file());
  const DatasetStats s = compute_stats(root, "bench", "bench");
  const fs::path out = fs::temp_directory_path() / "wheelpose_dataset_bench_stats";
  for (auto _ : state) write_stats_report({s}, out);
}
BENCHMARK(BM_StatsFigures)->Unit(benchmark::kSecond)->Iterations(1);

}  // namespace

int main(int argc, char** argv) {
  if (argc == 3 && std::strcmp(argv[1], "--write-only") == 0) {
    wheelpose::write_file_atomic(argv[2], synthetic_text());
    return 0;
  }
  std::fprintf(stderr, "synthetic COCO: %s\n", synthetic_file().c_str());
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
