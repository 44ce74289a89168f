// `wheelpose train`: fine-tune MoveNet MultiPose on COCO keypoint data (learn/trainer.h).

#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/allocator.h"
#include "core/error.h"
#include "learn/model_files.h"
#include "learn/trainer.h"
#include "progress.h"

namespace wheelpose::app {
namespace {

namespace fs = std::filesystem;

struct TrainCommandOptions {
  std::vector<std::string> train;
  std::string model = "movenet-multipose";
  std::string models;
  learn::TrainOptions run;
  std::string out;
  std::string val;
  std::string people_size;
};

// "MIN:MAX" in pixels.
void parse_people_size(const std::string& text, learn::AugmentOptions& augment) {
  const std::size_t colon = text.find(':');
  try {
    if (colon == std::string::npos) throw std::invalid_argument(text);
    std::size_t used_min = 0, used_max = 0;
    const std::string min_text = text.substr(0, colon), max_text = text.substr(colon + 1);
    augment.person_size_min = std::stod(min_text, &used_min);
    augment.person_size_max = std::stod(max_text, &used_max);
    if (used_min != min_text.size() || used_max != max_text.size()) {
      throw std::invalid_argument(text);
    }
  } catch (const std::exception&) {
    throw Error("--people-size " + text + ": expected MIN:MAX in pixels, e.g. 30:256");
  }
}

void run_train(TrainCommandOptions& c) {
  learn::TrainOptions o = c.run;
  for (const std::string& t : c.train) o.train.push_back(learn::parse_train_source(t));
  std::optional<fs::path> models_dir;
  if (!c.models.empty()) models_dir = fs::path(c.models);
  const learn::ModelChoice choice = learn::choose_model(c.model, models_dir);
  o.model_json = choice.topology;
  o.init_weights = choice.weights;
  o.out_dir = c.out;
  if (!c.val.empty()) o.val_coco = fs::path(c.val);
  if (!c.people_size.empty()) parse_people_size(c.people_size, o.augment);
  retain_large_blocks();
  Progress progress("train", "steps");
  const learn::TrainResult result = learn::train(
      o,
      [&](const learn::StepReport& r) {
        if (r.step % 10 == 0 || r.step == o.steps) {
          spdlog::info(
              "train: step {} loss {:.4f} (centre {:.3f}, heatmaps {:.3f}, regression {:.3f}, "
              "offsets {:.3f}, box {:.3f}+{:.3f}{}), {:.1f} images/s",
              r.step, r.loss, r.centre, r.keypoint_heatmap, r.keypoint_regression,
              r.keypoint_offset, r.box_scale, r.box_offset,
              o.distill > 0 ? fmt::format(", distill {:.3f}", r.distill) : "", r.images_per_second);
        }
        progress(r.step, o.steps);
      },
      [&](const learn::ValidationRow& v) {
        spdlog::info(
            "train: validation at step {}: keypoint AP {:.3f} (AP50 {:.3f}, AR {:.3f}), box AP "
            "{:.3f} (AP50 {:.3f})",
            v.step, v.keypoint_ap, v.keypoint_ap50, v.keypoint_ar, v.box_ap, v.box_ap50);
      });
  const int done = result.start_step + static_cast<int>(result.steps.size());
  spdlog::info("train: {} of {} steps done; weights in {}", done, o.steps,
               (fs::path(c.out) / "last.pt").string());
  if (result.best) {
    spdlog::info("train: best validation keypoint AP {:.3f} at step {}: {}",
                 result.best->keypoint_ap, result.best->step,
                 (fs::path(c.out) / "best.pt").string());
  }
}

}  // namespace

void attach_train(CLI::App& parent) {
  auto c = std::make_shared<TrainCommandOptions>();
  learn::TrainOptions& o = c->run;
  CLI::App* cmd = parent.add_subcommand(
      "train", "Fine-tune MoveNet MultiPose on COCO keypoint datasets (e.g. generated ones)");
  cmd->add_option("--train", c->train,
                  "COCO keypoints JSON, optionally :weight (images in images/ beside it or beside "
                  "the file); repeat to mix datasets")
      ->required();
  cmd->add_option("--model", c->model, "Start from: movenet-multipose or a .pt from train")
      ->capture_default_str();
  cmd->add_option("--models", c->models, "Folder of the models (as for predict)");
  cmd->add_option("--out", c->out, "Run folder: checkpoint.pt, last.pt, train_log.csv")->required();
  cmd->add_option("--steps", o.steps, "Optimizer steps")->capture_default_str();
  cmd->add_option("--batch", o.batch, "Images per step")->capture_default_str();
  cmd->add_option("--lr", o.learning_rate, "Peak learning rate (AdamW)")->capture_default_str();
  cmd->add_option("--weight-decay", o.weight_decay, "AdamW weight decay")->capture_default_str();
  cmd->add_option("--warmup", o.warmup_steps, "Linear warm-up steps, then cosine decay")
      ->capture_default_str();
  cmd->add_option("--freeze-backbone", o.freeze_backbone_steps,
                  "Train only the heads for the first N steps")
      ->capture_default_str();
  cmd->add_option("--backbone-lr-scale", o.backbone_lr_scale,
                  "The backbone's learning rate relative to the heads'")
      ->capture_default_str();
  cmd->add_option("--clip", o.clip_norm, "Gradient L2 norm cap")->capture_default_str();
  cmd->add_option("--checkpoint-every", o.checkpoint_every, "Steps between checkpoints")
      ->capture_default_str();
  cmd->add_option("--input-size", o.augment.input_size, "Square training input (x32)")
      ->capture_default_str();
  cmd->add_option("--people-scale", o.augment.target_longer_side,
                  "Show people at the scale predict --size N sees them")
      ->capture_default_str();
  cmd->add_option("--people-size", c->people_size,
                  "MIN:MAX: show each trained person with its longer box side log-uniform in "
                  "[MIN, MAX] input pixels, instead of at the --people-scale of its frame");
  cmd->add_option("--pull-to-start", o.pull_to_start,
                  "Each step, move every weight lr x this of the way back to its starting value "
                  "(0: off)")
      ->capture_default_str();
  cmd->add_option("--distill", o.distill,
                  "Weight of soft targets from the frozen start model's centre and keypoint "
                  "heatmaps on every batch (keeps what it knows; 0: off)")
      ->capture_default_str();
  cmd->add_option("--max-relative-step", o.max_relative_step,
                  "Cap each weight tensor's rate so that at the peak rate its step is at most "
                  "this fraction of the tensor's RMS (0: off)")
      ->capture_default_str();
  cmd->add_option("--offset-radius", o.offset_radius,
                  "Cells around each keypoint that also learn the offset to it, weighted by the "
                  "keypoint's Gaussian (0: its own cell only, CenterNet's rule)")
      ->capture_default_str();
  cmd->add_option("--loader-threads", o.loader_threads, "Batches prepared ahead in parallel")
      ->capture_default_str();
  cmd->add_option("--threads", o.threads, "Torch threads (0 = every core)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--seed", o.seed, "Seed of the image draws and augmentations")
      ->capture_default_str();
  cmd->add_option("--val", c->val,
                  "COCO keypoints JSON scored during training (keypoint and box AP); the best "
                  "weights are kept as best.pt");
  cmd->add_option("--val-every", o.val_every, "Steps between validations")->capture_default_str();
  cmd->add_option("--val-size", o.val_size, "Validation input size (as predict --size)")
      ->capture_default_str();
  cmd->add_option("--world-size", o.world_size,
                  "Processes training together (data parallel, Gloo); each takes batch / N")
      ->capture_default_str();
  cmd->add_option("--rank", o.rank, "This process's rank, 0 … world size − 1 (0 writes the files)")
      ->capture_default_str();
  cmd->add_option("--rendezvous", o.rendezvous,
                  "Where the processes meet: tcp://HOST:PORT (rank 0's host) or file:///PATH");
  cmd->add_flag("--resume", o.resume, "Continue the run in --out from its checkpoint");
  cmd->add_option("--stop-after", o.stop_after,
                  "Stop with a checkpoint after this many steps (continue with --resume)")
      ->check(CLI::NonNegativeNumber);
  cmd->callback([c] { run_train(*c); });
}

}  // namespace wheelpose::app
