#include "learn/trainer.h"

#include <spdlog/spdlog.h>
#include <torch/torch.h>

#include <chrono>
#include <cmath>
#include <deque>
#include <future>
#include <mutex>
#include <nlohmann/json.hpp>
#include <numbers>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <set>
#include <string>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/image_read.h"
#include "core/keypoint_template.h"
#include "learn/checkpoint.h"
#include "learn/data_parallel.h"
#include "learn/graph_module.h"
#include "learn/pose_predictor.h"
#include "learn/train_logs.h"
#include "learn/train_step.h"
#include "learn/training_curves.h"
#include "learn/validation.h"

namespace wheelpose::learn {
namespace {

namespace fs = std::filesystem;
using torch::Tensor;

struct Data {
  TrainSet set;
  std::vector<double> cumulative;
  std::vector<std::pair<int, int>> flip_pairs;
};

// Image `index` decoded, or, when it cannot be read (deleted, truncated, damaged since the run
// started), the next readable image of the set in order: a warning names each bad file once,
// and the batch stays a pure function of (seed, step) and the files on disk. Throws only when
// no image of the set can be read.
std::pair<const TrainImage&, cv::Mat> readable_image(const TrainSet& set, std::size_t index) {
  static std::mutex warned_mutex;
  static std::set<std::string> warned;
  for (std::size_t tried = 0; tried < set.images.size(); ++tried) {
    const TrainImage& image = set.images[(index + tried) % set.images.size()];
    try {
      return {image, read_image(image.file, cv::IMREAD_COLOR)};
    } catch (const Error& e) {
      const std::lock_guard lock(warned_mutex);
      if (warned.insert(image.file.string()).second) {
        spdlog::warn("train: skipping an image that cannot be read: {}", e.what());
      }
    }
  }
  throw Error("train: none of the " + std::to_string(set.images.size()) +
              " training images can be read");
}

// The augmented batch of optimizer step `step`: a pure function of (seed, step).
TrainBatch make_batch(const Data& data, const TrainOptions& o, std::int64_t step) {
  std::vector<TrainSample> samples;
  // This process's share: every world_size-th slot from its rank (the union over the ranks is
  // the batch one process would train on).
  for (int slot = o.rank; slot < o.batch; slot += o.world_size) {
    const std::size_t picked = pick_image(data.cumulative, o.seed, step, slot);
    auto [image, bgr] = readable_image(data.set, picked);
    cv::Mat rgb;
    cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
    samples.push_back(
        augment(rgb, image.people, data.flip_pairs, o.augment, o.seed,
                static_cast<std::uint64_t>(step) * static_cast<std::uint64_t>(o.batch) + slot));
  }
  return make_train_batch(samples, o.augment.input_size, o.offset_radius);
}

double learning_rate_at(const TrainOptions& o, int step) {
  if (step < o.warmup_steps) return o.learning_rate * (step + 1) / o.warmup_steps;
  const double span = std::max(1, o.steps - o.warmup_steps);
  const double t = std::min(1.0, (step - o.warmup_steps) / span);
  return o.learning_rate * (0.05 + 0.95 * 0.5 * (1 + std::cos(std::numbers::pi * t)));
}

void check(const TrainOptions& o) {
  auto bad = [](const std::string& what) { throw Error(what); };
  if (o.steps < 1) bad("--steps must be at least 1");
  if (o.batch < 1) bad("--batch must be at least 1");
  if (!(o.learning_rate > 0)) bad("--lr must be positive");
  if (o.warmup_steps < 1) bad("--warmup must be at least 1");
  if (o.checkpoint_every < 1) bad("--checkpoint-every must be at least 1");
  if (o.augment.input_size < 64 || o.augment.input_size > kMaxInputSide ||
      o.augment.input_size % 32 != 0) {
    bad("--input-size must be a multiple of 32 from 64 to " + std::to_string(kMaxInputSide));
  }
  if (o.loader_threads < 1) bad("--loader-threads must be at least 1");
  const AugmentOptions& a = o.augment;
  if (a.person_size_max > 0 && !(a.person_size_min > 0 && a.person_size_min <= a.person_size_max)) {
    bad("--people-size MIN:MAX needs 0 < MIN <= MAX");
  }
  if (o.pull_to_start < 0) bad("--pull-to-start must not be negative");
  if (o.distill < 0) bad("--distill must not be negative");
  if (o.max_relative_step < 0) bad("--max-relative-step must not be negative");
  if (o.offset_radius < 0 || o.offset_radius > kMaxOffsetRadius) {
    bad("--offset-radius must be 0 to " + std::to_string(kMaxOffsetRadius));
  }
  if (o.val_every < 1) bad("--val-every must be at least 1");
  if (o.world_size < 1) bad("--world-size must be at least 1");
  if (o.rank < 0 || o.rank >= o.world_size) bad("--rank must be in 0 … world size − 1");
  if (o.batch % o.world_size != 0) bad("--batch must be a multiple of --world-size");
  if (o.world_size > 1 && o.rendezvous.empty()) {
    bad("--world-size above 1 needs --rendezvous tcp://HOST:PORT or file:///PATH");
  }
}

// Weights are split in two groups: the heads, and the backbone at backbone_lr_scale of their
// rate (its folded batch norm makes it far more sensitive to a step than the heads are).
// With max_relative_step, every tensor is its own group instead, at a rate capped so that at
// the peak rate its Adam step (≈ the rate per element, whatever the gradient's size) is at
// most max_relative_step × the tensor's RMS: folded batch norm leaves some tensors with
// weights a thousand times smaller than their neighbours', and an equal step is a large
// change to them (one such tensor, moved 7 %, cost 4 keypoint AP on real photos).
struct RateGroup {
  std::vector<Tensor> tensors;
  double scale = 1;  // of the scheduled rate
  bool backbone = false;
};

std::vector<RateGroup> rate_groups(GraphModule& model, const TrainOptions& o) {
  std::vector<RateGroup> groups(2);
  groups[1].scale = o.backbone_lr_scale;
  groups[1].backbone = true;
  std::vector<RateGroup> per_tensor;
  for (const auto& p : model.named_parameters()) {
    const bool in_backbone = p.key().find("feature_extractor") != std::string::npos;
    groups[in_backbone ? 1 : 0].tensors.push_back(p.value());
    if (o.max_relative_step <= 0) continue;
    const double group_rate = o.learning_rate * (in_backbone ? o.backbone_lr_scale : 1.0);
    const double rms = p.value().detach().pow(2).mean().sqrt().item<double>();
    const double cap = rms > 0 && group_rate > 0 ? o.max_relative_step * rms / group_rate : 1.0;
    per_tensor.push_back(
        {{p.value()}, (in_backbone ? o.backbone_lr_scale : 1.0) * std::min(1.0, cap), in_backbone});
  }
  return o.max_relative_step > 0 ? per_tensor : groups;
}

// The training images, their cumulative draw weights and the flip pairs of COCO's 17 keypoints.
Data load_data(const TrainOptions& o) {
  Data data;
  data.set = load_train_set(o.train);
  for (const TrainImage& image : data.set.images) {
    data.cumulative.push_back((data.cumulative.empty() ? 0 : data.cumulative.back()) +
                              image.weight);
  }
  data.flip_pairs = load_keypoint_template("coco17").flip_pairs;
  spdlog::info("train: {} images, {} people with keypoints", data.set.images.size(),
               data.set.labelled_people);
  return data;
}

// Batches made on worker threads ahead of the optimizer, handed out in step order.
class BatchQueue {
 public:
  BatchQueue(const Data& data, const TrainOptions& o, int first_step)
      : data_(data), o_(o), next_to_load_(first_step) {}
  // Batches still being prepared finish before `data` goes away (futures from std::async
  // block in their destructors); they are simply dropped.
  ~BatchQueue() { ahead_.clear(); }

  TrainBatch next() {
    fill();
    TrainBatch batch = ahead_.front().get();
    ahead_.pop_front();
    fill();
    return batch;
  }

 private:
  void fill() {
    while (static_cast<int>(ahead_.size()) < o_.loader_threads + 1 && next_to_load_ < o_.steps) {
      ahead_.push_back(std::async(std::launch::async, make_batch, std::cref(data_), std::cref(o_),
                                  next_to_load_++));
    }
  }
  const Data& data_;
  const TrainOptions& o_;
  int next_to_load_;
  std::deque<std::future<TrainBatch>> ahead_;
};

// --val: scores weights with the validator (which only the writing process has), keeps
// val_log.csv and the best weights (best.pt, best.json).
class ValidationKeeper {
 public:
  ValidationKeeper(const TrainOptions& o, std::optional<Validator>& validator, int start_step,
                   TrainResult& result,
                   const std::function<void(const ValidationRow&)>& on_validation)
      : o_(o),
        validator_(validator),
        path_(o.out_dir / "val_log.csv"),
        log_(log_prefix(path_, start_step, kValLogHeader)),
        result_(result),
        on_validation_(on_validation) {
    for (const ValidationRow& r : parse_val_log(log_)) {
      if (!result_.best || r.keypoint_ap > result_.best->keypoint_ap) result_.best = r;
    }
  }

  bool due(int done) const {
    return validator_ && (done == 0 || done % o_.val_every == 0 || done == o_.steps);
  }

  // The starting weights (or, after a kill during a validation, the checkpoint's) are scored
  // first when their row is missing.
  void score_start(GraphModule& model, int start_step) {
    if (!due(start_step)) return;
    const std::vector<ValidationRow> done = parse_val_log(log_);
    if (done.empty() || done.back().step != start_step) score(model, start_step);
  }

  // Scores the current weights (saved as last.pt); the best so far becomes best.pt.
  void score(GraphModule& model, int done) {
    model.save(o_.out_dir / "last.pt");
    const ValidationScores v = validator_->score(o_.model_json, o_.out_dir / "last.pt");
    const ValidationRow row{done,          v.keypoint_ap, v.keypoint_ap50,
                            v.keypoint_ar, v.box_ap,      v.box_ap50};
    if (!result_.best || row.keypoint_ap > result_.best->keypoint_ap) {
      write_file_atomic(o_.out_dir / "best.pt", read_file(o_.out_dir / "last.pt"));
      write_file_atomic(o_.out_dir / "best.json", val_json(row).dump(2) + "\n");
      result_.best = row;
    }
    log_ += val_log_row(row);
    write_file_atomic(path_, log_);
    result_.validation.push_back(row);
    if (on_validation_) on_validation_(row);
  }

 private:
  const TrainOptions& o_;
  std::optional<Validator>& validator_;
  fs::path path_;
  std::string log_;
  TrainResult& result_;
  const std::function<void(const ValidationRow&)>& on_validation_;
};

// The step a run starts at: 0 for a new run (whose options.json it writes), the checkpoint's
// for --resume (restoring model and optimizer and writing last.pt from them).
int start_or_resume(const TrainOptions& o, bool writer, const std::string& key, GraphModule& model,
                    torch::optim::AdamW& optimizer) {
  if (o.resume) {
    const int step = load_checkpoint(model, optimizer, key, o.out_dir);
    spdlog::info("train: resuming at step {} of {}", step, o.steps);
    // last.pt always holds the weights a resumed run starts from, even if it was lost.
    if (writer) model.save(o.out_dir / "last.pt");
    return step;
  }
  if (fs::exists(o.out_dir / "checkpoint.pt")) {
    throw Error((o.out_dir / "checkpoint.pt").string() +
                " exists: pass --resume to continue that run, or another --out");
  }
  if (writer) {
    write_file_atomic(o.out_dir / "options.json", nlohmann::json::parse(key).dump(2) + "\n");
  }
  return 0;
}

}  // namespace

namespace {

// --pull-to-start: each weight moves lr × its group's scale × strength of the way back to its
// start.
void pull_toward(const std::vector<RateGroup>& groups,
                 const std::vector<std::vector<Tensor>>& start, double lr, double strength) {
  torch::NoGradGuard no_grad;
  for (std::size_t g = 0; g < start.size(); ++g) {
    const double rate = std::min(1.0, lr * groups[g].scale * strength);
    for (std::size_t i = 0; i < start[g].size(); ++i) {
      Tensor p = groups[g].tensors[i];
      p.sub_((p - start[g][i]) * rate);
    }
  }
}

}  // namespace

std::string resume_key(const TrainOptions& o) {
  nlohmann::json sources = nlohmann::json::array();
  for (const TrainSource& s : o.train) sources.push_back({s.coco.string(), s.weight});
  const AugmentOptions& a = o.augment;
  const nlohmann::json key = {{"train", sources},
                              {"model", o.model_json.filename().string()},
                              {"init_weights", o.init_weights ? o.init_weights->string() : ""},
                              {"steps", o.steps},
                              {"batch", o.batch},
                              {"learning_rate", o.learning_rate},
                              {"weight_decay", o.weight_decay},
                              {"warmup_steps", o.warmup_steps},
                              {"freeze_backbone_steps", o.freeze_backbone_steps},
                              {"backbone_lr_scale", o.backbone_lr_scale},
                              {"clip_norm", o.clip_norm},
                              {"seed", o.seed},
                              {"val", o.val_coco ? o.val_coco->string() : ""},
                              {"val_every", o.val_every},
                              {"val_size", o.val_size},
                              {"world_size", o.world_size},
                              {"augment",
                               {a.input_size, a.target_longer_side, a.scale_min, a.scale_max,
                                a.shift_fraction, a.rotate_degrees, a.flip_probability,
                                a.color_jitter, a.blur_probability, a.jpeg_probability}}};
  // Options added later join the key only when used, so earlier runs still resume.
  nlohmann::json extended = key;
  if (a.person_size_max > 0) extended["people_size"] = {a.person_size_min, a.person_size_max};
  if (o.pull_to_start > 0) extended["pull_to_start"] = o.pull_to_start;
  if (o.distill > 0) extended["distill"] = o.distill;
  if (o.max_relative_step > 0) extended["max_relative_step"] = o.max_relative_step;
  if (o.offset_radius > 0) extended["offset_radius"] = o.offset_radius;
  return extended.dump();
}

TrainResult train(const TrainOptions& o, const std::function<void(const StepReport&)>& on_step,
                  const std::function<void(const ValidationRow&)>& on_validation) {
  check(o);
  const bool writer = o.rank == 0;  // the one process that writes files
  std::optional<Validator> validator;
  if (o.val_coco && writer) validator.emplace(*o.val_coco, o.val_size, o.threads);
  const Data data = load_data(o);
  torch::set_num_threads(o.threads > 0 ? o.threads
                                       : std::max(1u, std::thread::hardware_concurrency()));
  GraphModule model(o.model_json);
  if (model.graph().outputs.size() != 1 ||
      model.graph().outputs[0].shape != std::vector<std::int64_t>{1, 6, 56}) {
    throw Error(o.model_json.string() + ": train fine-tunes MoveNet MultiPose (output 1×6×56)");
  }
  if (o.init_weights) model.load(*o.init_weights);
  model.train();
  const std::vector<RateGroup> groups = rate_groups(model, o);
  const torch::optim::AdamWOptions group_options =
      torch::optim::AdamWOptions(o.learning_rate).weight_decay(o.weight_decay);
  std::vector<torch::optim::OptimizerParamGroup> optimizer_groups;
  for (const RateGroup& g : groups) {
    optimizer_groups.emplace_back(g.tensors,
                                  std::make_unique<torch::optim::AdamWOptions>(group_options));
  }
  torch::optim::AdamW optimizer(std::move(optimizer_groups), group_options);
  // The weights --pull-to-start pulls toward: the start, before any resume.
  std::vector<std::vector<Tensor>> start_weights;
  if (o.pull_to_start > 0) {
    torch::NoGradGuard no_grad;
    for (const RateGroup& group : groups) {
      start_weights.emplace_back();
      for (const Tensor& p : group.tensors) start_weights.back().push_back(p.detach().clone());
    }
  }
  const auto set_backbone_trainable = [&](bool on) {
    for (const RateGroup& group : groups) {
      if (!group.backbone) continue;
      for (const Tensor& p : group.tensors) p.requires_grad_(on);
    }
  };

  // --distill's teacher: the start, frozen, before any resume.
  std::unique_ptr<GraphModule> teacher;
  if (o.distill > 0) {
    teacher = std::make_unique<GraphModule>(o.model_json);
    if (o.init_weights) teacher->load(*o.init_weights);
    for (const Tensor& p : teacher->parameters()) p.requires_grad_(false);
  }
  const Distillation distillation{teacher.get(), o.distill};

  ensure_directory(o.out_dir);
  const std::string key = resume_key(o);
  TrainResult result;
  result.start_step = start_or_resume(o, writer, key, model, optimizer);
  std::unique_ptr<GradientAverager> averager;
  if (o.world_size > 1) {
    spdlog::info("train: joining {} as rank {} of {}", o.rendezvous, o.rank, o.world_size);
    averager = std::make_unique<GradientAverager>(o.rendezvous, o.rank, o.world_size);
  }
  const std::vector<Tensor> parameters = model.parameters();
  const std::function<void(StepReport&)> average =
      averager ? std::function<void(StepReport&)>(
                     [&](StepReport& parts) { averager->average(parameters, parts); })
               : std::function<void(StepReport&)>();
  const fs::path log_path = o.out_dir / "train_log.csv";
  std::string log = log_prefix(log_path, result.start_step, kTrainLogHeader);
  ValidationKeeper validation(o, validator, result.start_step, result, on_validation);
  validation.score_start(model, result.start_step);

  BatchQueue batches(data, o, result.start_step);
  for (int step = result.start_step; step < o.steps; ++step) {
    const auto start = std::chrono::steady_clock::now();
    const TrainBatch batch = batches.next();
    set_backbone_trainable(step >= o.freeze_backbone_steps);
    const double lr = learning_rate_at(o, step);
    for (std::size_t g = 0; g < optimizer.param_groups().size(); ++g) {
      static_cast<torch::optim::AdamWOptions&>(optimizer.param_groups()[g].options())
          .lr(lr * groups[g].scale);
    }
    StepReport report =
        optimizer_step(model, optimizer, batch, o.clip_norm, step + 1, average, distillation);
    if (o.pull_to_start > 0) pull_toward(groups, start_weights, lr, o.pull_to_start);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    report.step = step + 1;
    report.learning_rate = lr;
    report.images_per_second = o.batch / std::max(seconds, 1e-9);
    log += train_log_row(report);
    result.steps.push_back(report);
    if (on_step) on_step(report);
    const bool stop = o.stop_after > 0 && report.step >= o.stop_after;
    const bool validating = validation.due(report.step);
    const bool checkpoint =
        report.step % o.checkpoint_every == 0 || report.step == o.steps || stop || validating;
    if (writer && checkpoint) {
      // The log first: killed between the two, the resume drops the rows past the older
      // checkpoint and trains them again; the other order would lose rows.
      write_file_atomic(log_path, log);
      save_checkpoint(model, optimizer, report.step, key, o.out_dir);
      if (validating) validation.score(model, report.step);
      draw_training_curves(o.out_dir);
    }
    if (stop) break;
  }
  set_backbone_trainable(true);
  return result;
}

}  // namespace wheelpose::learn
