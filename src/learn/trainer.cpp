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
#include "eval/keypoint_template.h"
#include "learn/graph_module.h"
#include "learn/movenet_targets.h"
#include "learn/training_curves.h"
#include "learn/validation.h"

namespace wheelpose::learn {
namespace {

namespace fs = std::filesystem;
using torch::Tensor;

// MoveNet MultiPose's head convolutions (NHWC outputs at stride 4, before any decoding).
const std::vector<std::string> kHeads = {
    "StatefulPartitionedCall/center_0/conv2d_4/BiasAdd",       // 1: person-centre logits
    "StatefulPartitionedCall/box_scale_0/conv2d_5/BiasAdd",    // 2: box (h, w) in cells
    "StatefulPartitionedCall/box_offset_0/conv2d_6/BiasAdd",   // 2: centre (dy, dx)
    "StatefulPartitionedCall/kpt_heatmap_0/conv2d_7/BiasAdd",  // 17: keypoint logits
    "StatefulPartitionedCall/kpt_regress_0/conv2d_8/BiasAdd",  // 34: keypoint − centre cell
    "StatefulPartitionedCall/kpt_offset_0/conv2d_9/BiasAdd",   // 34: keypoint − its cell
};

// Loss weights (CenterNet's: heatmaps and offsets 1, sizes 0.1; regression in cells 0.1).
constexpr double kCentreWeight = 1, kHeatmapWeight = 1, kRegressWeight = 0.1, kOffsetWeight = 1,
                 kScaleWeight = 0.1, kBoxOffsetWeight = 1;

struct Batch {
  Tensor images;                                             // B×S×S×3 float 0..255
  Tensor centre_heatmap;                                     // B×G×G×1
  Tensor keypoint_heatmap;                                   // B×G×G×17
  Tensor centre_index;                                       // N (b·G² + cell)
  Tensor regress, regress_mask, scale, box_offset;           // N×34, N×34, N×2, N×2
  Tensor keypoint_index, keypoint_channel, keypoint_offset;  // M, M, M×2
};

struct Data {
  TrainSet set;
  std::vector<double> cumulative;
  std::vector<std::pair<int, int>> flip_pairs;
};

Batch make_batch(const Data& data, const TrainOptions& o, std::int64_t step) {
  const int b = o.batch, s = o.augment.input_size, g = s / kOutputStride;
  Batch batch;
  batch.images = torch::empty({b, s, s, 3}, torch::kFloat);
  batch.centre_heatmap = torch::empty({b, g, g, 1}, torch::kFloat);
  batch.keypoint_heatmap = torch::empty({b, g, g, kKeypoints}, torch::kFloat);
  std::vector<std::int64_t> centre_index, keypoint_index, keypoint_channel;
  std::vector<float> regress, regress_mask, scale, box_offset, keypoint_offset;
  for (int slot = 0; slot < b; ++slot) {
    const TrainImage& image = data.set.images[pick_image(data.cumulative, o.seed, step, slot)];
    const cv::Mat bgr = cv::imread(image.file.string(), cv::IMREAD_COLOR);
    if (bgr.empty()) throw Error(image.file.string() + ": cannot decode image");
    cv::Mat rgb;
    cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
    const TrainSample sample =
        augment(rgb, image.people, data.flip_pairs, o.augment, o.seed,
                static_cast<std::uint64_t>(step) * static_cast<std::uint64_t>(b) + slot);
    const MovenetTargets t = build_targets(sample.people, s);
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
  return batch;
}

// CenterNet's penalty-reduced focal loss (α = 2, β = 4) over a heatmap, per positive cell.
Tensor focal_loss(const Tensor& logits, const Tensor& target) {
  const Tensor p = torch::sigmoid(logits).clamp(1e-4, 1 - 1e-4);
  const Tensor positive = target.ge(1.0).to(torch::kFloat);
  const Tensor pos_loss = torch::log(p) * (1 - p).pow(2) * positive;
  const Tensor neg_loss = torch::log(1 - p) * p.pow(2) * (1 - target).pow(4) * (1 - positive);
  return -(pos_loss.sum() + neg_loss.sum()) / positive.sum().clamp_min(1.0);
}

// Rows `index` of an NHWC head flattened to (B·G²)×C.
Tensor rows(const Tensor& head, const Tensor& index) {
  return head.reshape({-1, head.size(3)}).index_select(0, index);
}

struct Losses {
  Tensor total;
  StepReport parts;
};

Losses compute_losses(const TensorMap& heads, const Batch& b) {
  const Tensor& centre = heads.at(kHeads[0]);
  const Tensor& scale = heads.at(kHeads[1]);
  const Tensor& box_offset = heads.at(kHeads[2]);
  const Tensor& heatmap = heads.at(kHeads[3]);
  const Tensor& regress = heads.at(kHeads[4]);
  const Tensor& offset = heads.at(kHeads[5]);
  const double people = std::max<std::int64_t>(1, b.centre_index.size(0));
  const Tensor l_centre = focal_loss(centre, b.centre_heatmap) * kCentreWeight;
  const Tensor l_heatmap = focal_loss(heatmap, b.keypoint_heatmap) * kHeatmapWeight;
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
    l_offset = (at_k - b.keypoint_offset).abs().sum() /
               static_cast<double>(b.keypoint_index.size(0)) * kOffsetWeight;
  }
  Losses out;
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
  write_file_atomic(out_dir / "checkpoint.pt", bytes.str());
  model.save(out_dir / "last.pt");
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
                              {"augment",
                               {a.input_size, a.target_longer_side, a.scale_min, a.scale_max,
                                a.shift_fraction, a.rotate_degrees, a.flip_probability,
                                a.color_jitter, a.blur_probability, a.jpeg_probability}}};
  return key.dump();
}

TrainResult train(const TrainOptions& o, const std::function<void(const StepReport&)>& on_step,
                  const std::function<void(const ValidationRow&)>& on_validation) {
  check(o);
  std::optional<Validator> validator;
  if (o.val_coco) validator.emplace(*o.val_coco, o.val_size, o.threads);
  Data data;
  data.set = load_train_set(o.train);
  for (const TrainImage& image : data.set.images) {
    data.cumulative.push_back((data.cumulative.empty() ? 0 : data.cumulative.back()) +
                              image.weight);
  }
  data.flip_pairs = eval::load_keypoint_template("coco17").flip_pairs;
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
  } else {
    if (fs::exists(o.out_dir / "checkpoint.pt")) {
      throw Error((o.out_dir / "checkpoint.pt").string() +
                  " exists: pass --resume to continue that run, or another --out");
    }
    write_file_atomic(o.out_dir / "options.json", nlohmann::json::parse(key).dump(2) + "\n");
  }
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

  std::deque<std::future<Batch>> ahead;
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
    Batch batch = ahead.front().get();
    ahead.pop_front();
    fill();
    const bool frozen = step < o.freeze_backbone_steps;
    for (auto& [name, p] : backbone) p.requires_grad_(!frozen);
    const double lr = learning_rate_at(o, step);
    for (std::size_t g = 0; g < optimizer.param_groups().size(); ++g) {
      static_cast<torch::optim::AdamWOptions&>(optimizer.param_groups()[g].options())
          .lr(lr * group_scale[g]);
    }
    optimizer.zero_grad();
    const TensorMap heads = model.forward_only(batch.images, kHeads);
    Losses losses = compute_losses(heads, batch);
    if (!std::isfinite(losses.parts.loss)) {
      throw Error("train: the loss became " + std::to_string(losses.parts.loss) + " at step " +
                      std::to_string(step + 1) + "; lower --lr",
                  ErrorKind::kFailure);
    }
    losses.total.backward();
    torch::nn::utils::clip_grad_norm_(model.parameters(), o.clip_norm);
    optimizer.step();
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    StepReport report = losses.parts;
    report.step = step + 1;
    report.learning_rate = lr;
    report.images_per_second = o.batch / std::max(seconds, 1e-9);
    log += log_row(report);
    result.steps.push_back(report);
    if (on_step) on_step(report);
    const bool stop = o.stop_after > 0 && report.step >= o.stop_after;
    const bool validating = validation_due(report.step);
    if (report.step % o.checkpoint_every == 0 || report.step == o.steps || stop || validating) {
      save_checkpoint(model, optimizer, report.step, key, o.out_dir);
      write_file_atomic(log_path, log);
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
