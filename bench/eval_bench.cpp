// `wheelpose eval` speed on a synthetic COCO set: 5,000 images x 4 people, 10 detections per
// image (4 near the people, 6 clutter). Run: build/<dir>/bench/bench_eval

#include <benchmark/benchmark.h>

#include <nlohmann/json.hpp>

#include "core/coco_data.h"
#include "core/keypoint_template.h"
#include "core/random.h"
#include "eval/coco_eval.h"
#include "eval/keypoint_metrics.h"

namespace {

using namespace wheelpose::eval;
namespace coco = wheelpose::coco;
using wheelpose::KeypointTemplate;
using wheelpose::load_keypoint_template;

constexpr int kImages = 5000, kPeople = 4, kDetections = 10;

struct Synthetic {
  coco::CocoGroundTruth gt;
  coco::CocoResults dt;
};

const Synthetic& synthetic() {
  static const Synthetic data = [] {
    Synthetic s;
    s.gt.category_ids = {1};
    std::int64_t ann_id = 1;
    for (int i = 0; i < kImages; ++i) {
      s.gt.images.push_back({i + 1, "synthetic.jpg"});
      wheelpose::RandomStream rng(7, {"eval_bench", i});
      std::vector<coco::GtAnnotation> people;
      for (int p = 0; p < kPeople; ++p) {
        coco::GtAnnotation g;
        g.id = ann_id++;
        g.image_id = i + 1;
        g.category_id = 1;
        g.bbox = {rng.uniform(0, 500), rng.uniform(0, 300), rng.uniform(20, 150),
                  rng.uniform(40, 300)};
        g.area = g.bbox.w * g.bbox.h * 0.6;
        g.num_keypoints = 17;
        for (int k = 0; k < 17; ++k) {
          g.keypoints.push_back(g.bbox.x + rng.uniform(0, g.bbox.w));
          g.keypoints.push_back(g.bbox.y + rng.uniform(0, g.bbox.h));
          g.keypoints.push_back(rng.bernoulli(0.8) ? 2 : 1);
        }
        people.push_back(g);
        s.gt.annotations.push_back(std::move(g));
      }
      for (int d = 0; d < kDetections; ++d) {
        coco::Detection det;
        det.id = static_cast<std::int64_t>(s.dt.detections.size()) + 1;
        det.image_id = i + 1;
        det.category_id = 1;
        det.score = rng.uniform01();
        const coco::GtAnnotation& near = people[d % kPeople];
        const double noise = d < kPeople ? 4.0 : 40.0;
        for (int k = 0; k < 17; ++k) {
          det.keypoints.push_back(near.keypoints[3 * k] + rng.normal(0, noise));
          det.keypoints.push_back(near.keypoints[3 * k + 1] + rng.normal(0, noise));
          det.keypoints.push_back(1);
        }
        det.bbox = {near.bbox.x + rng.normal(0, noise), near.bbox.y + rng.normal(0, noise),
                    near.bbox.w, near.bbox.h};
        det.area = det.bbox.w * det.bbox.h;
        s.dt.detections.push_back(std::move(det));
      }
    }
    s.dt.has_keypoints = s.dt.has_bbox = true;
    return s;
  }();
  return data;
}

void BM_KeypointEval(benchmark::State& state) {
  const Synthetic& s = synthetic();
  const KeypointTemplate t = load_keypoint_template("coco17");
  for (auto _ : state) {
    CocoEvaluator evaluator(s.gt, s.dt, coco::IouType::kKeypoints, t);
    evaluator.evaluate();
    evaluator.accumulate();
    benchmark::DoNotOptimize(evaluator.summarize());
    benchmark::DoNotOptimize(compute_keypoint_metrics(evaluator, s.gt, s.dt, t));
  }
}
BENCHMARK(BM_KeypointEval)->Unit(benchmark::kMillisecond);

void BM_BboxEval(benchmark::State& state) {
  const Synthetic& s = synthetic();
  const KeypointTemplate t = load_keypoint_template("coco17");
  for (auto _ : state) benchmark::DoNotOptimize(run_coco_eval(s.gt, s.dt, coco::IouType::kBbox, t));
}
BENCHMARK(BM_BboxEval)->Unit(benchmark::kMillisecond);

// Parsing and validating the 50,000-entry results JSON, which the CLI does before evaluating.
void BM_LoadResults(benchmark::State& state) {
  const Synthetic& s = synthetic();
  nlohmann::json results = nlohmann::json::array();
  for (const coco::Detection& d : s.dt.detections) {
    results.push_back({{"image_id", d.image_id},
                       {"category_id", 1},
                       {"score", d.score},
                       {"keypoints", d.keypoints},
                       {"bbox", {d.bbox.x, d.bbox.y, d.bbox.w, d.bbox.h}}});
  }
  const std::string text = results.dump();
  for (auto _ : state) {
    benchmark::DoNotOptimize(
        coco::parse_coco_results(nlohmann::json::parse(text), "bench.json", s.gt, 17));
  }
  state.counters["MB"] = static_cast<double>(text.size()) / 1e6;
}
BENCHMARK(BM_LoadResults)->Unit(benchmark::kMillisecond);

}  // namespace
