#pragma once
// `wheelpose train`: fine-tunes MoveNet MultiPose on COCO keypoint data (learn/train_data.h,
// learn/movenet_targets.h) with CenterNet's losses, AdamW, linear warm-up then cosine decay,
// gradient clipping and an optional frozen backbone. Deterministic in the seed: step s always
// trains on the same augmented batch, so a resumed run continues exactly. Torch-free header.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "learn/train_data.h"

namespace wheelpose::learn {

// --offset-radius's largest value: beyond 8 cells (32 input pixels) a cell is far outside any
// keypoint's heatmap peak, where the decoder never reads an offset.
inline constexpr int kMaxOffsetRadius = 8;

struct TrainOptions {
  std::vector<TrainSource> train;
  std::filesystem::path model_json;                   // the topology (movenet-multipose)
  std::optional<std::filesystem::path> init_weights;  // start from a .pt instead
  std::filesystem::path out_dir;
  int steps = 1000;
  int batch = 16;
  // The heads' rate. Adam on the pretrained net with its folded batch norm is fragile: one
  // step at 2.5e-5 on every parameter multiplied the centre loss by 1000, the heads alone are
  // stable at 1e-4 — hence the backbone's much lower rate. The pilot in docs/results.md used these.
  double learning_rate = 1e-4;
  double weight_decay = 1e-4;
  int warmup_steps = 50;
  int freeze_backbone_steps = 0;    // train only the heads for the first N steps
  double backbone_lr_scale = 0.05;  // the backbone's learning rate relative to the heads'
  double clip_norm = 5.0;           // gradient L2 norm cap
  // > 0: after every step each weight moves lr × pull_to_start of the way back to its starting
  // value (AdamW's decoupled decay, aimed at the pretrained weights instead of zero), so the
  // weights stay within about 1 / pull_to_start of where they began: what the pretrained model
  // knows of real people is kept while it learns wheelchair users.
  double pull_to_start = 0;
  // > 0: distillation from the frozen start model (Learning without Forgetting, Li & Hoiem
  // 2016): its person-centre and keypoint heatmaps on each training batch become soft targets
  // away from the labelled people (weighted by 1 − the label heatmaps), at this weight. Keeps
  // the start's scores where the labels say nothing new. Costs one extra forward pass per step.
  double distill = 0;
  // > 0: each weight tensor's rate is capped so that at the peak rate its step is at most this
  // fraction of the tensor's RMS (Adam moves every weight by about the rate whatever its size;
  // see rate_groups in trainer.cpp). 0: the two groups' rates as they are.
  double max_relative_step = 0;
  // Cells around each keypoint that learn the offset to it too (learn/movenet_targets.h): the
  // pretrained MultiPose decodes from a field of offsets, not from one cell, and one-cell
  // targets cost 2–4 keypoint AP on real photos (docs/results.md, "The offset field"). 0:
  // CenterNet's one cell.
  int offset_radius = 2;
  int checkpoint_every = 100;
  int loader_threads = 1;  // batches prepared ahead, each on its own thread
  int threads = 0;         // torch intra-op threads; 0 = every core
  std::uint64_t seed = 1;
  bool resume = false;
  int stop_after = 0;  // > 0: stop (with a checkpoint) once this many steps are done in total
  // Validation: keypoint and box AP on this COCO file (scored as `predict --size val_size` +
  // `eval` would) before the first step, every val_every steps and at the end; the weights
  // with the best keypoint AP are kept as best.pt.
  std::optional<std::filesystem::path> val_coco;
  // Data parallelism (learn/data_parallel.h): world_size processes, each computing `batch /
  // world_size` of every batch; rank 0 writes every file. Needs a rendezvous
  // ("tcp://HOST:PORT" or "file:///PATH") when world_size > 1.
  int world_size = 1;
  int rank = 0;
  std::string rendezvous;
  int val_every = 250;
  int val_size = 640;
  AugmentOptions augment;
};

// One optimizer step's losses (already weighted) and speed.
struct StepReport {
  int step = 0;  // 1-based, steps done
  double learning_rate = 0;
  double loss = 0, centre = 0, keypoint_heatmap = 0, keypoint_regression = 0, keypoint_offset = 0,
         box_scale = 0, box_offset = 0, distill = 0;
  double images_per_second = 0;
};

struct ValidationRow {
  int step = 0;  // steps done when scored (0: the starting weights)
  double keypoint_ap = 0, keypoint_ap50 = 0, keypoint_ar = 0, box_ap = 0, box_ap50 = 0;
};

struct TrainResult {
  int start_step = 0;                     // > 0 after --resume
  std::vector<StepReport> steps;          // the steps this call ran
  std::vector<ValidationRow> validation;  // the validations this call ran
  std::optional<ValidationRow> best;      // with --val: the best so far (best.pt holds it)
};

// Writes into out_dir: checkpoint.pt (model, optimizer, step; replaced atomically every
// checkpoint_every steps, at each validation and at the end), last.pt (weights, loadable by
// `predict --model`), train_log.csv (one row per step, appended on resume), options.json and
// curves.png/.svg (learn/training_curves.h); with val_coco also val_log.csv, best.pt and
// best.json. With `resume`, the
// options must equal the checkpoint's (else Error, checkpoint untouched). Throws Error for bad
// data or options.
TrainResult train(const TrainOptions& options,
                  const std::function<void(const StepReport&)>& on_step = {},
                  const std::function<void(const ValidationRow&)>& on_validation = {});

// The options that must not change between a run and its resume, as canonical JSON text.
std::string resume_key(const TrainOptions& options);

}  // namespace wheelpose::learn
