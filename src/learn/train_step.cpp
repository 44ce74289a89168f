#include "learn/train_step.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"
#include "learn/movenet_targets.h"

namespace wheelpose::learn {

using torch::Tensor;

// MoveNet MultiPose's head convolutions (NHWC outputs at stride 4, before any decoding).
const std::vector<std::string> kMovenetHeads = {
    "StatefulPartitionedCall/center_0/conv2d_4/BiasAdd",       // 1: person-centre logits
    "StatefulPartitionedCall/box_scale_0/conv2d_5/BiasAdd",    // 2: box (h, w) in cells
    "StatefulPartitionedCall/box_offset_0/conv2d_6/BiasAdd",   // 2: centre (dy, dx)
    "StatefulPartitionedCall/kpt_heatmap_0/conv2d_7/BiasAdd",  // 17: keypoint logits
    "StatefulPartitionedCall/kpt_regress_0/conv2d_8/BiasAdd",  // 34: keypoint − centre cell
    "StatefulPartitionedCall/kpt_offset_0/conv2d_9/BiasAdd",   // 34: keypoint − its cell
};

namespace {

// Loss weights (CenterNet's: heatmaps and offsets 1, sizes 0.1; regression in cells 0.1).
constexpr double kCentreWeight = 1, kHeatmapWeight = 1, kRegressWeight = 0.1, kOffsetWeight = 1,
                 kScaleWeight = 0.1, kBoxOffsetWeight = 1;

// CenterNet's penalty-reduced focal loss (α = 2, β = 4) over a heatmap, per positive cell.
// `weight` (B×G×G×1, broadcast over channels; undefined = all 1) scales each cell's negative
// term: crowd regions are neither positive nor negative.
Tensor focal_loss(const Tensor& logits, const Tensor& target, const Tensor& weight) {
  const Tensor p = torch::sigmoid(logits).clamp(1e-4, 1 - 1e-4);
  const Tensor positive = target.ge(1.0).to(torch::kFloat);
  const Tensor pos_loss = torch::log(p) * (1 - p).pow(2) * positive;
  Tensor neg_loss = torch::log(1 - p) * p.pow(2) * (1 - target).pow(4) * (1 - positive);
  if (weight.defined()) neg_loss = neg_loss * weight;
  return -(pos_loss.sum() + neg_loss.sum()) / positive.sum().clamp_min(1.0);
}

// Rows `index` of an NHWC head flattened to (B·G²)×C.
Tensor rows(const Tensor& head, const Tensor& index) {
  return head.reshape({-1, head.size(3)}).index_select(0, index);
}

}  // namespace

TrainBatch make_train_batch(const std::vector<TrainSample>& samples, int input_size,
                            int offset_radius) {
  WHEELPOSE_CHECK(input_size % kOutputStride == 0 && !samples.empty());
  const int b = static_cast<int>(samples.size()), s = input_size, g = s / kOutputStride;
  TrainBatch batch;
  batch.images = torch::empty({b, s, s, 3}, torch::kFloat);
  batch.centre_heatmap = torch::empty({b, g, g, 1}, torch::kFloat);
  batch.keypoint_heatmap = torch::empty({b, g, g, kKeypoints}, torch::kFloat);
  std::vector<std::int64_t> centre_index, keypoint_index, keypoint_channel;
  std::vector<float> regress, regress_mask, scale, box_offset, keypoint_offset, keypoint_weight;
  std::vector<MovenetTargets> all_targets;
  all_targets.reserve(samples.size());
  bool any_crowd = false;
  for (int slot = 0; slot < b; ++slot) {
    const TrainSample& sample = samples[slot];
    WHEELPOSE_CHECK(sample.rgb.rows == s && sample.rgb.cols == s && sample.rgb.type() == CV_8UC3);
    const MovenetTargets& t =
        all_targets.emplace_back(build_targets(sample.people, s, offset_radius));
    any_crowd |= !t.heatmap_weight.empty();
    cv::Mat f;
    sample.rgb.convertTo(f, CV_32FC3);
    batch.images[slot].copy_(torch::from_blob(f.data, {s, s, 3}, torch::kFloat));
    batch.centre_heatmap[slot].copy_(
        torch::from_blob(const_cast<float*>(t.centre_heatmap.data()), {g, g, 1}, torch::kFloat));
    batch.keypoint_heatmap[slot].copy_(torch::from_blob(
        const_cast<float*>(t.keypoint_heatmap.data()), {g, g, kKeypoints}, torch::kFloat));
    const std::int64_t base = static_cast<std::int64_t>(slot) * g * g;
    for (const CentreTarget& c : t.centres) {
      centre_index.push_back(base + c.cell);
      regress.insert(regress.end(), c.regress.begin(), c.regress.end());
      for (float m : c.regress_mask) regress_mask.insert(regress_mask.end(), {m, m});
      scale.insert(scale.end(), c.scale.begin(), c.scale.end());
      box_offset.insert(box_offset.end(), c.offset.begin(), c.offset.end());
    }
    for (const KeypointTarget& k : t.keypoints) {
      keypoint_index.push_back(base + k.cell);
      keypoint_channel.push_back(k.keypoint);
      keypoint_offset.insert(keypoint_offset.end(), k.offset.begin(), k.offset.end());
      keypoint_weight.push_back(k.weight);
    }
  }
  if (any_crowd) {
    batch.heatmap_weight = torch::ones({b, g, g, 1}, torch::kFloat);
    for (int slot = 0; slot < b; ++slot) {
      const std::vector<float>& w = all_targets[slot].heatmap_weight;
      if (w.empty()) continue;
      batch.heatmap_weight[slot].copy_(
          torch::from_blob(const_cast<float*>(w.data()), {g, g, 1}, torch::kFloat));
    }
  }
  auto longs = [](const std::vector<std::int64_t>& v) { return torch::tensor(v, torch::kLong); };
  auto floats = [](const std::vector<float>& v, std::int64_t columns) {
    return torch::tensor(v, torch::kFloat).reshape({-1, columns});
  };
  batch.centre_index = longs(centre_index);
  batch.regress = floats(regress, 2 * kKeypoints);
  batch.regress_mask = floats(regress_mask, 2 * kKeypoints);
  batch.scale = floats(scale, 2);
  batch.box_offset = floats(box_offset, 2);
  batch.keypoint_index = longs(keypoint_index);
  batch.keypoint_channel = longs(keypoint_channel);
  batch.keypoint_offset = floats(keypoint_offset, 2);
  if (std::any_of(keypoint_weight.begin(), keypoint_weight.end(), [](float w) { return w != 1; })) {
    batch.keypoint_weight = torch::tensor(keypoint_weight, torch::kFloat);
  }
  return batch;
}

StepLosses compute_losses(const TensorMap& heads, const TrainBatch& b) {
  const Tensor& centre = heads.at(kMovenetHeads[0]);
  const Tensor& scale = heads.at(kMovenetHeads[1]);
  const Tensor& box_offset = heads.at(kMovenetHeads[2]);
  const Tensor& heatmap = heads.at(kMovenetHeads[3]);
  const Tensor& regress = heads.at(kMovenetHeads[4]);
  const Tensor& offset = heads.at(kMovenetHeads[5]);
  const double people = std::max<std::int64_t>(1, b.centre_index.size(0));
  const Tensor l_centre = focal_loss(centre, b.centre_heatmap, b.heatmap_weight) * kCentreWeight;
  const Tensor l_heatmap =
      focal_loss(heatmap, b.keypoint_heatmap, b.heatmap_weight) * kHeatmapWeight;
  Tensor l_regress = torch::zeros({}), l_scale = torch::zeros({}), l_box = torch::zeros({}),
         l_offset = torch::zeros({});
  if (b.centre_index.size(0) > 0) {
    l_regress = (rows(regress, b.centre_index) - b.regress).abs().mul(b.regress_mask).sum() /
                b.regress_mask.sum().clamp_min(1.0) * kRegressWeight;
    l_scale = (rows(scale, b.centre_index) - b.scale).abs().sum() / people * kScaleWeight;
    l_box =
        (rows(box_offset, b.centre_index) - b.box_offset).abs().sum() / people * kBoxOffsetWeight;
  }
  if (b.keypoint_index.size(0) > 0) {
    // Keypoint k's (dy, dx) are channels 2k and 2k + 1.
    const Tensor picked = rows(offset, b.keypoint_index).reshape({-1, kKeypoints, 2});
    const Tensor at_k =
        picked.gather(1, b.keypoint_channel.view({-1, 1, 1}).expand({-1, 1, 2})).squeeze(1);
    const Tensor error = (at_k - b.keypoint_offset).abs();
    l_offset = b.keypoint_weight.defined()
                   ? error.sum(1).mul(b.keypoint_weight).sum() / b.keypoint_weight.sum()
                   : error.sum() / static_cast<double>(b.keypoint_index.size(0));
    l_offset = l_offset * kOffsetWeight;
  }
  StepLosses out;
  out.total = l_centre + l_heatmap + l_regress + l_offset + l_scale + l_box;
  out.parts.loss = out.total.item<double>();
  out.parts.centre = l_centre.item<double>();
  out.parts.keypoint_heatmap = l_heatmap.item<double>();
  out.parts.keypoint_regression = l_regress.item<double>();
  out.parts.keypoint_offset = l_offset.item<double>();
  out.parts.box_scale = l_scale.item<double>();
  out.parts.box_offset = l_box.item<double>();
  return out;
}

Tensor distillation_loss(const TensorMap& student, const TensorMap& teacher,
                         const Tensor& centre_labels, const Tensor& keypoint_labels) {
  Tensor total = torch::zeros({});
  const std::pair<const std::string&, const Tensor&> heads[] = {
      {kMovenetHeads[0], centre_labels}, {kMovenetHeads[3], keypoint_labels}};
  for (const auto& [head, labels] : heads) {
    const Tensor& s = student.at(head);
    const Tensor t = teacher.at(head).detach();
    const Tensor p = torch::sigmoid(t);
    // BCE(student, p) − BCE(teacher, p): the KL divergence, exactly 0 at agreement.
    const Tensor kl = torch::binary_cross_entropy_with_logits(s, p, {}, {}, at::Reduction::None) -
                      torch::binary_cross_entropy_with_logits(t, p, {}, {}, at::Reduction::None);
    total = total + (kl * (1 - labels)).sum() / static_cast<double>(s.size(0));
  }
  return total;
}

StepReport optimizer_step(GraphModule& model, torch::optim::Optimizer& optimizer,
                          const TrainBatch& batch, double clip_norm, int step_number,
                          const std::function<void(StepReport&)>& after_backward,
                          const Distillation& distillation) {
  optimizer.zero_grad();
  const TensorMap heads = model.forward_only(batch.images, kMovenetHeads);
  StepLosses losses = compute_losses(heads, batch);
  if (distillation.teacher != nullptr && distillation.weight > 0) {
    TensorMap teacher_heads;
    {
      torch::NoGradGuard no_grad;
      teacher_heads = distillation.teacher->forward_only(batch.images, kMovenetHeads);
    }
    const Tensor l_distill =
        distillation_loss(heads, teacher_heads, batch.centre_heatmap, batch.keypoint_heatmap) *
        distillation.weight;
    losses.total = losses.total + l_distill;
    losses.parts.distill = l_distill.item<double>();
    losses.parts.loss += losses.parts.distill;
  }
  if (!std::isfinite(losses.parts.loss)) {
    throw Error("train: the loss became " + std::to_string(losses.parts.loss) + " at step " +
                    std::to_string(step_number) + "; lower --lr",
                ErrorKind::kFailure);
  }
  losses.total.backward();
  if (after_backward) after_backward(losses.parts);
  torch::nn::utils::clip_grad_norm_(model.parameters(), clip_norm);
  optimizer.step();
  return losses.parts;
}

}  // namespace wheelpose::learn
