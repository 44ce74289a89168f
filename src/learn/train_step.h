#pragma once
// One optimizer step of MoveNet MultiPose fine-tuning: a batch of augmented samples with their
// CenterNet targets (learn/movenet_targets.h) as tensors, the weighted losses, and zero-grad →
// forward → backward → clip → step. Internal to `learn` (includes torch): trainer.cpp loops
// it over the data, train_probe.cpp times it for the benchmark.

#include <torch/torch.h>

#include <functional>
#include <string>
#include <vector>

#include "learn/graph_module.h"
#include "learn/train_data.h"
#include "learn/trainer.h"

namespace wheelpose::learn {

// The head convolutions trained, NHWC at stride 4, before the graph's own decoding.
extern const std::vector<std::string> kMovenetHeads;

struct TrainBatch {
  torch::Tensor images;            // B×S×S×3 float 0..255
  torch::Tensor centre_heatmap;    // B×G×G×1
  torch::Tensor keypoint_heatmap;  // B×G×G×17
  // B×G×G×1, 0 in crowd regions (MovenetTargets::heatmap_weight); undefined when no sample of
  // the batch has one, so batches without crowds compute exactly what they did before.
  torch::Tensor heatmap_weight;
  torch::Tensor centre_index;                                       // N (b·G² + cell)
  torch::Tensor regress, regress_mask, scale, box_offset;           // N×34, N×34, N×2, N×2
  torch::Tensor keypoint_index, keypoint_channel, keypoint_offset;  // M, M, M×2
  // M: each offset target's weight (MovenetTargets); undefined when every one is 1 (offset
  // radius 0), so those batches compute exactly what they did before.
  torch::Tensor keypoint_weight;
};

// Samples of input_size² (augment's output) with their targets (offsets within
// `offset_radius` cells of each keypoint: build_targets), as one batch.
TrainBatch make_train_batch(const std::vector<TrainSample>& samples, int input_size,
                            int offset_radius = 0);

struct StepLosses {
  torch::Tensor total;  // differentiable
  StepReport parts;     // loss and its parts as numbers (step, rate and speed left 0)
};

// The weighted CenterNet losses of the heads' outputs against the batch's targets.
StepLosses compute_losses(const TensorMap& heads, const TrainBatch& batch);

// --distill: the frozen start model and the weight of its soft targets (no teacher: off).
struct Distillation {
  GraphModule* teacher = nullptr;
  double weight = 0;
};

// Binary KL divergence of the student's person-centre and keypoint heatmaps from the
// teacher's, each cell weighted by 1 − its label heatmap value (the labels rule at the people
// they mark, the teacher everywhere else), summed over cells and channels, averaged over the
// batch; 0 when they agree.
torch::Tensor distillation_loss(const TensorMap& student, const TensorMap& teacher,
                                const torch::Tensor& centre_labels,
                                const torch::Tensor& keypoint_labels);

// One step; throws Error (kFailure) naming `step_number` when the loss is not finite.
// `after_backward`, when given, runs between backward and clipping with the loss parts (data
// parallelism averages the gradients and the parts over the processes there).
StepReport optimizer_step(GraphModule& model, torch::optim::Optimizer& optimizer,
                          const TrainBatch& batch, double clip_norm, int step_number,
                          const std::function<void(StepReport&)>& after_backward = {},
                          const Distillation& distillation = {});

}  // namespace wheelpose::learn
