#include "learn/trainer.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/atomic_file.h"
#include "learn/graph_module.h"
#include "learn/learn_test_support.h"

namespace wheelpose::learn {
namespace {

using testing::write_skier_set;

namespace fs = std::filesystem;

fs::path multipose_topology() {
  return fs::path(WHEELPOSE_SOURCE_DIR) / "models" / "movenet-multipose.json";
}

// A short run on the skier set: 128² inputs, lr 1e-3 from the first step, 2 threads.
TrainOptions skier_run(const fs::path& gt, const fs::path& out_dir, int steps, int batch) {
  TrainOptions o;
  o.train = {{gt, 1}};
  o.model_json = multipose_topology();
  o.out_dir = out_dir;
  o.steps = steps;
  o.batch = batch;
  o.learning_rate = 1e-3;
  o.warmup_steps = 1;
  o.threads = 2;
  o.augment.input_size = 128;
  return o;
}

// With every augmentation off, each step sees the same crop of the COCO sample's skier, so the
// heads (backbone frozen) must fit it: the loss falls well below where it started.
TEST(Trainer, LossFallsOnAFixedSample) {
  const fs::path topology = multipose_topology();
  if (!fs::exists(topology)) GTEST_SKIP() << "MoveNet models missing: run scripts/setup.sh";
  const fs::path dir = fs::temp_directory_path() / "wheelpose_trainer_test";
  const fs::path gt = write_skier_set(dir);

  TrainOptions o = skier_run(gt, dir / "run", 12, 2);
  o.freeze_backbone_steps = 12;
  o.augment = testing::no_augmentation(128, 160);
  const TrainResult r = train(o);
  ASSERT_EQ(r.steps.size(), 12u);
  const double first = r.steps.front().loss;
  double last = 0;
  for (int i = 9; i < 12; ++i) last += r.steps[i].loss / 3;
  std::printf("[ NOTE ] loss %.3f -> %.3f\n", first, last);
  EXPECT_LT(last, 0.7 * first);
  fs::remove_all(dir);
}

// --pull-to-start at full strength (lr × strength ≥ 1 in both groups) puts every weight back
// at its start after each step, so last.pt holds the pretrained weights (to one rounding); off,
// the same steps move them.
TEST(Trainer, FullPullToStartKeepsThePretrainedWeights) {
  const fs::path topology = multipose_topology();
  if (!fs::exists(topology)) GTEST_SKIP() << "MoveNet models missing: run scripts/setup.sh";
  const fs::path dir = fs::temp_directory_path() / "wheelpose_trainer_pull_test";
  const fs::path gt = write_skier_set(dir);
  GraphModule pretrained(topology);
  auto same_as_pretrained = [&](const fs::path& weights) {
    GraphModule trained(topology);
    trained.load(weights);
    const auto a = pretrained.named_parameters(), b = trained.named_parameters();
    bool same = a.size() == b.size();
    // p − (p − start) is the start within one rounding.
    for (const auto& p : a) same = same && torch::allclose(p.value(), b[p.key()], 1e-6, 1e-7);
    return same;
  };
  for (const double pull : {0.0, 1e9}) {
    TrainOptions o = skier_run(gt, dir / ("run-" + std::to_string(pull > 0)), 2, 1);
    o.pull_to_start = pull;
    train(o);
    EXPECT_EQ(same_as_pretrained(o.out_dir / "last.pt"), pull > 0) << "pull " << pull;
  }
  fs::remove_all(dir);
}

// --distill: before the first update the student is its teacher, so step 1's distillation
// term is 0 (to rounding); once the weights move it is positive, and it lands in train_log.csv.
TEST(Trainer, DistillationStartsAtZeroAndGrows) {
  const fs::path topology = multipose_topology();
  if (!fs::exists(topology)) GTEST_SKIP() << "MoveNet models missing: run scripts/setup.sh";
  const fs::path dir = fs::temp_directory_path() / "wheelpose_trainer_distill_test";
  const fs::path gt = write_skier_set(dir);
  TrainOptions o = skier_run(gt, dir / "run", 3, 1);
  o.distill = 2;
  const TrainResult r = train(o);
  ASSERT_EQ(r.steps.size(), 3u);
  EXPECT_NEAR(r.steps[0].distill, 0.0, 1e-4);
  EXPECT_GT(r.steps[2].distill, 1e-3);
  const double parts = r.steps[2].centre + r.steps[2].keypoint_heatmap +
                       r.steps[2].keypoint_regression + r.steps[2].keypoint_offset +
                       r.steps[2].box_scale + r.steps[2].box_offset + r.steps[2].distill;
  EXPECT_NEAR(r.steps[2].loss, parts, 1e-3 * parts);
  const std::string log = read_file(o.out_dir / "train_log.csv");
  EXPECT_NE(log.find(",distill,"), std::string::npos);
  fs::remove_all(dir);
}

// --max-relative-step: Adam moves each weight by about the rate per step whatever its size, so
// uncapped, the tensor with the smallest weights changes by a large fraction of itself; capped,
// no tensor's RMS change exceeds steps × the cap (Adam's step is at most ~1.5 × the rate in
// its first steps).
TEST(Trainer, RelativeStepCapBoundsEveryTensorsChange) {
  const fs::path topology = multipose_topology();
  if (!fs::exists(topology)) GTEST_SKIP() << "MoveNet models missing: run scripts/setup.sh";
  const fs::path dir = fs::temp_directory_path() / "wheelpose_trainer_relative_test";
  const fs::path gt = write_skier_set(dir);
  GraphModule pretrained(topology);
  const auto largest_relative_change = [&](const fs::path& weights) {
    GraphModule trained(topology);
    trained.load(weights);
    const auto after = trained.named_parameters();
    double largest = 0;
    for (const auto& p : pretrained.named_parameters()) {
      const double rms = p.value().pow(2).mean().sqrt().item<double>();
      const double moved = (after[p.key()] - p.value()).pow(2).mean().sqrt().item<double>();
      if (rms > 0) largest = std::max(largest, moved / rms);
    }
    return largest;
  };
  const double cap = 1e-4;
  TrainOptions o = skier_run(gt, dir / "capped", 2, 1);
  o.max_relative_step = cap;
  train(o);
  const double capped = largest_relative_change(o.out_dir / "last.pt");
  o.out_dir = dir / "uncapped";
  o.max_relative_step = 0;
  train(o);
  const double uncapped = largest_relative_change(o.out_dir / "last.pt");
  std::printf("[ NOTE ] largest relative change: capped %.2e, uncapped %.2e\n", capped, uncapped);
  EXPECT_GT(capped, 0.0);
  EXPECT_LE(capped, 2 * 1.5 * cap);
  EXPECT_GT(uncapped, 10 * capped);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace wheelpose::learn
