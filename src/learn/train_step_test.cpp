#include "learn/train_step.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>

#include "learn/graph_module.h"
#include "learn/learn_test_support.h"
#include "learn/train_data.h"

namespace wheelpose::learn {
namespace {

namespace fs = std::filesystem;

// Heads shaped like the model's (B×G×G×C): only the two heatmaps take part in distillation.
TensorMap heads_with(const torch::Tensor& centre, const torch::Tensor& keypoints) {
  return {{kMovenetHeads[0], centre}, {kMovenetHeads[3], keypoints}};
}

// One cell, teacher probability 0.75 against a student at 0.5: KL = 0.75 ln 1.5 + 0.25 ln 0.5.
TEST(Distillation, LossIsTheBinaryKlDivergence) {
  const torch::Tensor teacher_logit = torch::full({1, 1, 1, 1}, std::log(3.0));
  const torch::Tensor zero = torch::zeros({1, 1, 1, 1});
  const torch::Tensor no_keypoints = torch::zeros({1, 1, 1, 17});
  const double kl = 0.75 * std::log(1.5) + 0.25 * std::log(0.5);
  const TensorMap student = heads_with(zero, no_keypoints);
  const TensorMap teacher = heads_with(teacher_logit, no_keypoints);
  const auto loss_with_label = [&](double label) {
    return distillation_loss(student, teacher, torch::full({1, 1, 1, 1}, label), no_keypoints)
        .item<double>();
  };
  EXPECT_NEAR(loss_with_label(0), kl, 1e-6);
  // A label heatmap of 0.25 there leaves three quarters of it; a labelled peak (1) none.
  EXPECT_NEAR(loss_with_label(0.25), 0.75 * kl, 1e-6);
  EXPECT_EQ(loss_with_label(1), 0.0);
}

// Zero where student and teacher agree, positive elsewhere, averaged over the batch, and its
// gradient moves the student's logits toward the teacher's.
TEST(Distillation, VanishesAtAgreementAndPullsTowardTheTeacher) {
  torch::manual_seed(3);
  const torch::Tensor centre = torch::randn({2, 8, 8, 1}) * 3;
  const torch::Tensor keypoints = torch::randn({2, 8, 8, 17}) * 3;
  const TensorMap teacher = heads_with(centre, keypoints);
  const torch::Tensor centre_labels = torch::zeros({2, 8, 8, 1});
  const torch::Tensor keypoint_labels = torch::zeros({2, 8, 8, 17});
  const auto loss_of = [](const TensorMap& a, const TensorMap& b) {
    return distillation_loss(a, b, torch::zeros_like(b.at(kMovenetHeads[0])),
                             torch::zeros_like(b.at(kMovenetHeads[3])));
  };
  EXPECT_NEAR(loss_of(teacher, teacher).item<double>(), 0.0, 1e-4);

  const torch::Tensor student_centre = centre.clone().add_(1.0).requires_grad_(true);
  const torch::Tensor student_keypoints = keypoints.clone().requires_grad_(true);
  const torch::Tensor loss = distillation_loss(heads_with(student_centre, student_keypoints),
                                               teacher, centre_labels, keypoint_labels);
  EXPECT_GT(loss.item<double>(), 0.01);
  loss.backward();
  // Every centre logit sits 1 above the teacher's: the gradient is positive everywhere.
  EXPECT_GT(student_centre.grad().min().item<double>(), 0.0);
  EXPECT_NEAR(student_keypoints.grad().abs().max().item<double>(), 0.0, 1e-6);

  // A batch of the same image twice scores as the image once.
  const TensorMap one = heads_with(centre.slice(0, 0, 1), keypoints.slice(0, 0, 1));
  const TensorMap one_shifted = heads_with(centre.slice(0, 0, 1) + 1.0, keypoints.slice(0, 0, 1));
  const TensorMap twice =
      heads_with(torch::cat({centre.slice(0, 0, 1), centre.slice(0, 0, 1)}),
                 torch::cat({keypoints.slice(0, 0, 1), keypoints.slice(0, 0, 1)}));
  const TensorMap twice_shifted =
      heads_with(torch::cat({centre.slice(0, 0, 1), centre.slice(0, 0, 1)}) + 1.0,
                 torch::cat({keypoints.slice(0, 0, 1), keypoints.slice(0, 0, 1)}));
  EXPECT_NEAR(loss_of(twice_shifted, twice).item<double>(),
              loss_of(one_shifted, one).item<double>(), 1e-4);
}

// A crowd region's cells are neither positive nor negative: a confident detection there costs
// nothing, while without the region it is a false positive.
TEST(CrowdRegions, ConfidenceInsideARegionCostsNothing) {
  TrainSample sample;
  sample.rgb = cv::Mat::zeros(64, 64, CV_8UC3);
  TrainPerson person;
  person.box = {36, 36, 20, 20};  // centre cell (11, 11) of the 16 × 16 grid
  person.keypoints[3 * 5] = 40, person.keypoints[3 * 5 + 1] = 40, person.keypoints[3 * 5 + 2] = 2;
  TrainPerson crowd;
  crowd.box = {0, 0, 24, 24};  // cells 0..5 × 0..5
  crowd.ignore = true;
  sample.people = {person};
  const TrainBatch plain = make_train_batch({sample}, 64);
  EXPECT_FALSE(plain.heatmap_weight.defined());
  sample.people = {person, crowd};
  const TrainBatch with_crowd = make_train_batch({sample}, 64);
  ASSERT_TRUE(with_crowd.heatmap_weight.defined());

  const auto heads = [](double inside) {
    torch::Tensor centre = torch::full({1, 16, 16, 1}, -6.0);
    torch::Tensor heatmap = torch::full({1, 16, 16, 17}, -6.0);
    centre.index_put_({0, torch::indexing::Slice(0, 6), torch::indexing::Slice(0, 6)}, inside);
    heatmap.index_put_({0, torch::indexing::Slice(0, 6), torch::indexing::Slice(0, 6)}, inside);
    return TensorMap{{kMovenetHeads[0], centre},
                     {kMovenetHeads[1], torch::zeros({1, 16, 16, 2})},
                     {kMovenetHeads[2], torch::zeros({1, 16, 16, 2})},
                     {kMovenetHeads[3], heatmap},
                     {kMovenetHeads[4], torch::zeros({1, 16, 16, 34})},
                     {kMovenetHeads[5], torch::zeros({1, 16, 16, 34})}};
  };
  const StepReport quiet = compute_losses(heads(-6.0), with_crowd).parts;
  const StepReport confident = compute_losses(heads(6.0), with_crowd).parts;
  EXPECT_DOUBLE_EQ(confident.centre, quiet.centre);
  EXPECT_DOUBLE_EQ(confident.keypoint_heatmap, quiet.keypoint_heatmap);
  // Without the region the same confidence is punished.
  EXPECT_GT(compute_losses(heads(6.0), plain).parts.centre, quiet.centre + 1.0);
  // Outside regions nothing changes: with background values in the region's 36 cells the two
  // batches differ only by those cells' tiny negative terms.
  EXPECT_NEAR(compute_losses(heads(-6.0), plain).parts.centre, quiet.centre, 1e-5);
}

// The COCO sample's skier as a 256² batch, unaugmented, with offsets taught `offset_radius`
// cells around each keypoint.
TrainBatch unaugmented_skier_batch(const std::string& name, int offset_radius) {
  const testing::TempDir dir(name);
  const TrainSet set = load_train_set({{testing::write_skier_set(dir.path() / "set"), 1}});
  const TrainImage& skier = set.images.at(0);
  cv::Mat rgb;
  cv::cvtColor(cv::imread(skier.file.string()), rgb, cv::COLOR_BGR2RGB);
  return make_train_batch(
      {augment(rgb, skier.people, {}, testing::no_augmentation(256, 256), 1, 0)}, 256,
      offset_radius);
}

// The targets follow the conventions the pretrained MoveNet was trained with: on the COCO
// sample's skier, unaugmented, its own heads land where build_targets puts them, so a swapped
// axis, a half-cell shift or other units in any head fail here. Measured: the centre peak one
// cell off (the box centre sits on a cell corner), box size within 1 %, regression 0.6 cells
// off on average, keypoints decoded at each heatmap's peak shifted by (0.16, 0.29) cells.
TEST(TargetConventions, ThePretrainedModelAgreesWithTheTargets) {
  WHEELPOSE_REQUIRE_MODEL("movenet-multipose");
  const TrainBatch b = unaugmented_skier_batch("conventions", 0);
  ASSERT_EQ(b.centre_index.size(0), 1);
  GraphModule model(testing::model_json("movenet-multipose"));
  const torch::NoGradGuard no_grad;
  const TensorMap heads = model.forward_only(b.images, kMovenetHeads);
  const auto per_cell = [&](int head) {
    const torch::Tensor& h = heads.at(kMovenetHeads[head]);
    return h.reshape({-1, h.size(3)});
  };
  const int grid = 64, target_cell = b.centre_index[0].item<int>();
  const int peak = per_cell(0).argmax().item<int>();
  EXPECT_LE(std::abs(peak / grid - target_cell / grid), 1);
  EXPECT_LE(std::abs(peak % grid - target_cell % grid), 1);

  const torch::Tensor scale = per_cell(1)[target_cell];
  EXPECT_NEAR((scale / b.scale[0] - 1).abs().max().item<double>(), 0.0, 0.05);
  const double regress_error =
      (per_cell(4)[target_cell] - b.regress[0]).abs().mul(b.regress_mask[0]).sum().item<double>() /
      b.regress_mask[0].sum().item<double>();
  EXPECT_LT(regress_error, 1.0);

  // Each keypoint decoded as the graph does: its heatmap's peak cell plus that cell's offset.
  double shift_y = 0, shift_x = 0;
  const int labelled = static_cast<int>(b.keypoint_index.size(0));
  ASSERT_GE(labelled, 15);
  for (int i = 0; i < labelled; ++i) {
    const int k = b.keypoint_channel[i].item<int>(), cell = b.keypoint_index[i].item<int>();
    const int at = per_cell(3).select(1, k).argmax().item<int>();
    shift_y += at / grid + per_cell(5)[at][2 * k].item<double>() -
               (cell / grid + b.keypoint_offset[i][0].item<double>());
    shift_x += at % grid + per_cell(5)[at][2 * k + 1].item<double>() -
               (cell % grid + b.keypoint_offset[i][1].item<double>());
  }
  EXPECT_LT(std::hypot(shift_y, shift_x) / labelled, 0.45)
      << "mean shift " << shift_y / labelled << ", " << shift_x / labelled << " cells";
}

// The pretrained MultiPose's offsets form a field: from the cells around a keypoint they point
// at it, as build_targets' offset radius teaches (one-cell targets leave those cells free).
// On the skier the cells one step from each keypoint's own cell miss it by 0.49 cells on
// average (its own cells by about 0.3); had they copied their keypoint's own cell's offset they
// would miss by 1.25.
TEST(TargetConventions, ThePretrainedOffsetsAroundAKeypointPointAtIt) {
  WHEELPOSE_REQUIRE_MODEL("movenet-multipose");
  const TrainBatch b = unaugmented_skier_batch("offset-field", 1);
  ASSERT_TRUE(b.keypoint_weight.defined());
  GraphModule model(testing::model_json("movenet-multipose"));
  const torch::NoGradGuard no_grad;
  const torch::Tensor offsets =
      model.forward_only(b.images, kMovenetHeads).at(kMovenetHeads[5]).reshape({-1, 34});
  // Each cell's miss if the offsets are a field (the target there) and if they are not (the
  // keypoint's own cell's target, copied).
  double field_miss = 0, copied_miss = 0;
  int around = 0;
  const auto distance = [&](int cell, int k, const torch::Tensor& target) {
    return std::hypot(offsets[cell][2 * k].item<double>() - target[0].item<double>(),
                      offsets[cell][2 * k + 1].item<double>() - target[1].item<double>());
  };
  for (int i = 0; i < b.keypoint_index.size(0); ++i) {
    if (b.keypoint_weight[i].item<float>() != 1.f) continue;
    const int k = b.keypoint_channel[i].item<int>();
    for (int j = 0; j < b.keypoint_index.size(0); ++j) {
      if (j == i || b.keypoint_channel[j].item<int>() != k) continue;
      const int cell = b.keypoint_index[j].item<int>();
      field_miss += distance(cell, k, b.keypoint_offset[j]);
      copied_miss += distance(cell, k, b.keypoint_offset[i]);
      ++around;
    }
  }
  ASSERT_GE(around, 15 * 8);
  EXPECT_LT(field_miss, copied_miss / 2)
      << around << " cells: " << field_miss / around << " against " << copied_miss / around;
}

// Weighted offset targets: the loss is the weighted mean of their L1 errors.
TEST(TrainStep, TheOffsetLossWeighsEachCellsTarget) {
  TrainSample sample;
  sample.rgb = cv::Mat::zeros(64, 64, CV_8UC3);
  TrainPerson person;
  person.box = {20, 10, 20, 40};
  person.keypoints[0] = 30.5, person.keypoints[1] = 20.5, person.keypoints[2] = 2;
  sample.people = {person};
  EXPECT_FALSE(make_train_batch({sample}, 64, 0).keypoint_weight.defined());
  const TrainBatch b = make_train_batch({sample}, 64, 1);
  ASSERT_TRUE(b.keypoint_weight.defined());
  ASSERT_EQ(b.keypoint_index.size(0), 9);
  TensorMap heads{{kMovenetHeads[0], torch::zeros({1, 16, 16, 1})},
                  {kMovenetHeads[1], torch::zeros({1, 16, 16, 2})},
                  {kMovenetHeads[2], torch::zeros({1, 16, 16, 2})},
                  {kMovenetHeads[3], torch::zeros({1, 16, 16, 17})},
                  {kMovenetHeads[4], torch::zeros({1, 16, 16, 34})},
                  {kMovenetHeads[5], torch::zeros({1, 16, 16, 34})}};
  double weighted = 0, weights = 0;
  for (int i = 0; i < 9; ++i) {
    const double w = b.keypoint_weight[i].item<double>();
    weighted += w * b.keypoint_offset[i].abs().sum().item<double>();
    weights += w;
  }
  EXPECT_NEAR(compute_losses(heads, b).parts.keypoint_offset, weighted / weights, 1e-6);
  // The exact field: no offset loss.
  torch::Tensor field = torch::zeros({16 * 16, 34});
  for (int i = 0; i < 9; ++i) {
    field[b.keypoint_index[i].item<int>()].slice(0, 0, 2) = b.keypoint_offset[i];
  }
  heads[kMovenetHeads[5]] = field.reshape({1, 16, 16, 34});
  EXPECT_NEAR(compute_losses(heads, b).parts.keypoint_offset, 0.0, 1e-6);
}

}  // namespace
}  // namespace wheelpose::learn
