#include "learn/trainer.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/atomic_file.h"
#include "learn/learn_test_support.h"

namespace wheelpose::learn {
namespace {

namespace fs = std::filesystem;

// With every augmentation off, each step sees the same crop of the COCO sample's skier, so the
// heads (backbone frozen) must fit it: the loss falls well below where it started.
TEST(Trainer, LossFallsOnAFixedSample) {
  const fs::path shared = fs::path(WHEELPOSE_SHARED_DIR) / "data" / "coco-sample";
  const fs::path topology = fs::path(WHEELPOSE_SOURCE_DIR) / "models" / "movenet-multipose.json";
  if (!fs::exists(topology)) GTEST_SKIP() << "MoveNet models missing: run scripts/setup.sh";
  const fs::path dir = fs::temp_directory_path() / "wheelpose_trainer_test";
  fs::remove_all(dir);
  fs::create_directories(dir);
  nlohmann::json gt = nlohmann::json::parse(read_file(shared / "person_keypoints_sample.json"));
  nlohmann::json images = nlohmann::json::array(), annotations = nlohmann::json::array();
  for (const auto& image : gt["images"]) {
    if (image["file_name"] == "000000000785.jpg") images.push_back(image);
  }
  for (const auto& a : gt["annotations"]) {
    if (a["image_id"] == images.at(0)["id"]) annotations.push_back(a);
  }
  gt["images"] = images;
  gt["annotations"] = annotations;
  write_file_atomic(dir / "gt.json", gt.dump());
  fs::copy_file(shared / "000000000785.jpg", dir / "000000000785.jpg");

  TrainOptions o;
  o.train = {{dir / "gt.json", 1}};
  o.model_json = topology;
  o.out_dir = dir / "run";
  o.steps = 12;
  o.batch = 2;
  o.learning_rate = 1e-3;
  o.warmup_steps = 1;
  o.freeze_backbone_steps = 12;
  o.checkpoint_every = 100;
  o.threads = 2;
  o.augment = {.input_size = 128,
               .target_longer_side = 160,
               .scale_min = 1,
               .scale_max = 1,
               .shift_fraction = 0,
               .rotate_degrees = 0,
               .flip_probability = 0,
               .color_jitter = 0,
               .blur_probability = 0,
               .jpeg_probability = 0};
  const TrainResult r = train(o);
  ASSERT_EQ(r.steps.size(), 12u);
  const double first = r.steps.front().loss;
  double last = 0;
  for (int i = 9; i < 12; ++i) last += r.steps[i].loss / 3;
  std::printf("[ NOTE ] loss %.3f -> %.3f\n", first, last);
  EXPECT_LT(last, 0.7 * first);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace wheelpose::learn
