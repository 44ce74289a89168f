#include "learn/trainer.h"

#include <spdlog/spdlog.h>
#include <torch/torch.h>

#include <chrono>
#include <cmath>
#include <deque>
#include <fstream>
#include <future>
#include <nlohmann/json.hpp>
#include <numbers>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/keypoint_template.h"
#include "learn/data_parallel.h"
#include "learn/graph_module.h"
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

// The augmented batch of optimizer step `step`: a pure function of (seed, step).
TrainBatch make_batch(const Data& data, const TrainOptions& o, std::int64_t step) {
  std::vector<TrainSample> samples;
  // This process's share: every world_size-th slot from its rank (the union over the ranks is
  // the batch one process would train on).
  for (int slot = o.rank; slot < o.batch; slot += o.world_size) {
    const TrainImage& image = data.set.images[pick_image(data.cumulative, o.seed, step, slot)];
    const cv::Mat bgr = cv::imread(image.file.string(), cv::IMREAD_COLOR);
    if (bgr.empty()) throw Error(image.file.string() + ": cannot decode image");
    cv::Mat rgb;
    cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
    samples.push_back(
        augment(rgb, image.people, data.flip_pairs, o.augment, o.seed,
                static_cast<std::uint64_t>(step) * static_cast<std::uint64_t>(o.batch) + slot));
  }
  return make_train_batch(samples, o.augment.input_size);
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
  if (o.augment.input_size < 64 || o.augment.input_size % 32 != 0) {
    bad("--input-size must be a multiple of 32, at least 64");
  }
  if (o.loader_threads < 1) bad("--loader-threads must be at least 1");
  if (o.val_every < 1) bad("--val-every must be at least 1");
  if (o.world_size < 1) bad("--world-size must be at least 1");
  if (o.rank < 0 || o.rank >= o.world_size) bad("--rank must be in 0 … world size − 1");
  if (o.batch % o.world_size != 0) bad("--batch must be a multiple of --world-size");
  if (o.world_size > 1 && o.rendezvous.empty()) {
    bad("--world-size above 1 needs --rendezvous tcp://HOST:PORT or file:///PATH");
  }
}

const char* const kLogHeader =
    "step,learning_rate,loss,centre,keypoint_heatmap,keypoint_regression,keypoint_offset,"
    "box_scale,box_offset,images_per_second\n";

std::string log_row(const StepReport& r) {
  std::ostringstream row;
  row.precision(6);
  row << r.step << ',' << r.learning_rate << ',' << r.loss << ',' << r.centre << ','
      << r.keypoint_heatmap << ',' << r.keypoint_regression << ',' << r.keypoint_offset << ','
      << r.box_scale << ',' << r.box_offset << ',' << r.images_per_second << '\n';
  return row.str();
}

const char* const kValHeader = "step,keypoint_ap,keypoint_ap50,keypoint_ar,box_ap,box_ap50\n";

std::string val_row(const ValidationRow& r) {
  std::ostringstream row;
  row.precision(6);
  row << r.step << ',' << r.keypoint_ap << ',' << r.keypoint_ap50 << ',' << r.keypoint_ar << ','
      << r.box_ap << ',' << r.box_ap50 << '\n';
  return row.str();
}

// A CSV log's header and its rows up to `step` (a killed run may have logged past its last
// checkpoint; those steps run again).
std::string log_prefix(const fs::path& path, int step, const std::string& header) {
  std::string kept = header;
  if (!fs::exists(path)) return kept;
  std::istringstream in(read_file(path));
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    if (std::stoi(line.substr(0, line.find(','))) > step) break;
    kept += line + '\n';
  }
  return kept;
}

// The validation rows of a val_log.csv text.
std::vector<ValidationRow> parse_val_log(const std::string& text) {
  std::vector<ValidationRow> rows;
  std::istringstream in(text);
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    std::istringstream fields(line);
    ValidationRow r;
    char comma = 0;
    fields >> r.step >> comma >> r.keypoint_ap >> comma >> r.keypoint_ap50 >> comma >>
        r.keypoint_ar >> comma >> r.box_ap >> comma >> r.box_ap50;
    rows.push_back(r);
  }
  return rows;
}

nlohmann::json val_json(const ValidationRow& r) {
  return {{"step", r.step},
          {"keypoint_ap", r.keypoint_ap},
          {"keypoint_ap50", r.keypoint_ap50},
          {"keypoint_ar", r.keypoint_ar},
          {"box_ap", r.box_ap},
          {"box_ap50", r.box_ap50}};
}

void save_checkpoint(GraphModule& model, torch::optim::AdamW& optimizer, int step,
                     const std::string& key, const fs::path& out_dir) {
  torch::serialize::OutputArchive archive;
  for (const auto& p : model.named_parameters()) archive.write("model/" + p.key(), p.value());
  torch::serialize::OutputArchive optimizer_archive;
  optimizer.save(optimizer_archive);
  archive.write("optimizer", optimizer_archive);
  archive.write("step", torch::tensor(static_cast<std::int64_t>(step)));
  archive.write("resume_key", c10::IValue(key));
  std::ostringstream bytes;
  archive.save_to(bytes);
  // last.pt first: killed between the two, the resume starts from the older checkpoint and
  // writes last.pt again; the other order would leave a stale last.pt behind a final checkpoint.
  model.save(out_dir / "last.pt");
  write_file_atomic(out_dir / "checkpoint.pt", bytes.str());
}

int load_checkpoint(GraphModule& model, torch::optim::AdamW& optimizer, const std::string& key,
                    const fs::path& out_dir) {
  const fs::path path = out_dir / "checkpoint.pt";
  if (!fs::exists(path)) throw Error(path.string() + ": no checkpoint to resume from");
  torch::serialize::InputArchive archive;
  try {
    archive.load_from(path.string());
    c10::IValue stored_key;
    archive.read("resume_key", stored_key);
    if (!stored_key.isString() || stored_key.toStringRef() != key) {
      throw Error(path.string() + ": written with other settings; resume needs the same " +
                  "--train, --model, --steps, --batch, --lr, --seed, … as the first run (see " +
                  (out_dir / "options.json").string() + ")");
    }
    torch::NoGradGuard no_grad;
    for (auto& p : model.named_parameters()) {
      Tensor value;
      archive.read("model/" + p.key(), value);
      p.value().copy_(value);
    }
    torch::serialize::InputArchive optimizer_archive;
    archive.read("optimizer", optimizer_archive);
    optimizer.load(optimizer_archive);
    Tensor step;
    archive.read("step", step);
    return static_cast<int>(step.item<std::int64_t>());
  } catch (const c10::Error& e) {
    throw Error(path.string() + ": not a checkpoint of this model (" +
                std::string(e.what_without_backtrace()).substr(0, 160) + ")");
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
  return key.dump();
}

TrainResult train(const TrainOptions& o, const std::function<void(const StepReport&)>& on_step,
                  const std::function<void(const ValidationRow&)>& on_validation) {
  check(o);
  const bool writer = o.rank == 0;  // the one process that writes files
  std::optional<Validator> validator;
  if (o.val_coco && writer) validator.emplace(*o.val_coco, o.val_size, o.threads);
  Data data;
  data.set = load_train_set(o.train);
  for (const TrainImage& image : data.set.images) {
    data.cumulative.push_back((data.cumulative.empty() ? 0 : data.cumulative.back()) +
                              image.weight);
  }
  data.flip_pairs = load_keypoint_template("coco17").flip_pairs;
  spdlog::info("train: {} images, {} people with keypoints", data.set.images.size(),
               data.set.labelled_people);

  torch::set_num_threads(o.threads > 0 ? o.threads
                                       : std::max(1u, std::thread::hardware_concurrency()));
  GraphModule model(o.model_json);
  if (model.graph().outputs.size() != 1 ||
      model.graph().outputs[0].shape != std::vector<std::int64_t>{1, 6, 56}) {
    throw Error(o.model_json.string() + ": train fine-tunes MoveNet MultiPose (output 1×6×56)");
  }
  if (o.init_weights) model.load(*o.init_weights);
  model.train();
  // Two groups: the heads, and the backbone at backbone_lr_scale of their rate (its folded
  // batch norm makes it far more sensitive to a step than the heads are).
  std::vector<Tensor> head_params, backbone_params;
  std::vector<std::pair<std::string, Tensor>> backbone;
  for (const auto& p : model.named_parameters()) {
    const bool in_backbone = p.key().find("feature_extractor") != std::string::npos;
    (in_backbone ? backbone_params : head_params).push_back(p.value());
    if (in_backbone) backbone.emplace_back(p.key(), p.value());
  }
  const torch::optim::AdamWOptions group_options =
      torch::optim::AdamWOptions(o.learning_rate).weight_decay(o.weight_decay);
  torch::optim::AdamW optimizer(
      {torch::optim::OptimizerParamGroup(
           head_params, std::make_unique<torch::optim::AdamWOptions>(group_options)),
       torch::optim::OptimizerParamGroup(
           backbone_params, std::make_unique<torch::optim::AdamWOptions>(group_options))},
      group_options);
  const std::vector<double> group_scale = {1.0, o.backbone_lr_scale};

  ensure_directory(o.out_dir);
  const std::string key = resume_key(o);
  TrainResult result;
  if (o.resume) {
    result.start_step = load_checkpoint(model, optimizer, key, o.out_dir);
    spdlog::info("train: resuming at step {} of {}", result.start_step, o.steps);
    // last.pt always holds the weights a resumed run starts from, even if it was lost.
    if (writer) model.save(o.out_dir / "last.pt");
  } else {
    if (fs::exists(o.out_dir / "checkpoint.pt")) {
      throw Error((o.out_dir / "checkpoint.pt").string() +
                  " exists: pass --resume to continue that run, or another --out");
    }
    if (writer) {
      write_file_atomic(o.out_dir / "options.json", nlohmann::json::parse(key).dump(2) + "\n");
    }
  }
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
  std::string log = log_prefix(log_path, result.start_step, kLogHeader);
  const fs::path val_log_path = o.out_dir / "val_log.csv";
  std::string val_log = log_prefix(val_log_path, result.start_step, kValHeader);
  for (const ValidationRow& r : parse_val_log(val_log)) {
    if (!result.best || r.keypoint_ap > result.best->keypoint_ap) result.best = r;
  }
  auto validation_due = [&](int done) {
    return validator && (done == 0 || done % o.val_every == 0 || done == o.steps);
  };
  // Scores the current weights (saved as last.pt); the best so far becomes best.pt.
  auto validate = [&](int done) {
    model.save(o.out_dir / "last.pt");
    const ValidationScores v = validator->score(o.model_json, o.out_dir / "last.pt");
    const ValidationRow row{done,          v.keypoint_ap, v.keypoint_ap50,
                            v.keypoint_ar, v.box_ap,      v.box_ap50};
    if (!result.best || row.keypoint_ap > result.best->keypoint_ap) {
      write_file_atomic(o.out_dir / "best.pt", read_file(o.out_dir / "last.pt"));
      write_file_atomic(o.out_dir / "best.json", val_json(row).dump(2) + "\n");
      result.best = row;
    }
    val_log += val_row(row);
    write_file_atomic(val_log_path, val_log);
    result.validation.push_back(row);
    if (on_validation) on_validation(row);
  };
  // The starting weights (or, after a kill during a validation, the checkpoint's) are scored
  // first when their row is missing.
  if (validation_due(result.start_step)) {
    const std::vector<ValidationRow> done = parse_val_log(val_log);
    if (done.empty() || done.back().step != result.start_step) validate(result.start_step);
  }

  std::deque<std::future<TrainBatch>> ahead;
  int next_to_load = result.start_step;
  auto fill = [&] {
    while (static_cast<int>(ahead.size()) < o.loader_threads + 1 && next_to_load < o.steps) {
      ahead.push_back(std::async(std::launch::async, make_batch, std::cref(data), std::cref(o),
                                 next_to_load++));
    }
  };
  for (int step = result.start_step; step < o.steps; ++step) {
    const auto start = std::chrono::steady_clock::now();
    fill();
    TrainBatch batch = ahead.front().get();
    ahead.pop_front();
    fill();
    const bool frozen = step < o.freeze_backbone_steps;
    for (auto& [name, p] : backbone) p.requires_grad_(!frozen);
    const double lr = learning_rate_at(o, step);
    for (std::size_t g = 0; g < optimizer.param_groups().size(); ++g) {
      static_cast<torch::optim::AdamWOptions&>(optimizer.param_groups()[g].options())
          .lr(lr * group_scale[g]);
    }
    StepReport report = optimizer_step(model, optimizer, batch, o.clip_norm, step + 1, average);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    report.step = step + 1;
    report.learning_rate = lr;
    report.images_per_second = o.batch / std::max(seconds, 1e-9);
    log += log_row(report);
    result.steps.push_back(report);
    if (on_step) on_step(report);
    const bool stop = o.stop_after > 0 && report.step >= o.stop_after;
    const bool validating = validation_due(report.step);
    const bool checkpoint =
        report.step % o.checkpoint_every == 0 || report.step == o.steps || stop || validating;
    if (writer && checkpoint) {
      // The log first: killed between the two, the resume drops the rows past the older
      // checkpoint and trains them again; the other order would lose rows.
      write_file_atomic(log_path, log);
      save_checkpoint(model, optimizer, report.step, key, o.out_dir);
      if (validating) validate(report.step);
      draw_training_curves(o.out_dir);
    }
    if (stop) break;
  }
  // Batches already being prepared finish before `data` goes away (futures from std::async
  // block in their destructors); they are simply dropped.
  ahead.clear();
  for (auto& [name, p] : backbone) p.requires_grad_(true);
  return result;
}

}  // namespace wheelpose::learn
