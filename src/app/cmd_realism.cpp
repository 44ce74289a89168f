// `wheelpose realism`: how a model trained on real photos sees a dataset's people, overall and by
// every attribute the dataset records (eval/realism.h).

#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <string>
#include <vector>

#include "app/cli_checks.h"
#include "core/atomic_file.h"
#include "core/coco_data.h"
#include "core/error.h"
#include "core/image_read.h"
#include "core/keypoint_template.h"
#include "eval/realism.h"
#include "learn/model_files.h"
#include "learn/pose_predictor.h"
#include "progress.h"

namespace wheelpose::app {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

struct RealismCommandOptions {
  std::string dataset, images, model = "movenet-multipose", models, dt, out;
  std::vector<int> sizes = {256, 640};
  int threads = 0;
  eval::RealismOptions realism;
};

// A `generate` folder (annotations.json + images/) or a COCO file with its images folder.
std::pair<fs::path, fs::path> dataset_files(const RealismCommandOptions& o) {
  std::error_code ec;
  const fs::path dataset(o.dataset);
  if (fs::is_directory(dataset, ec)) {
    const fs::path gt = dataset / "annotations.json";
    if (!fs::is_regular_file(gt, ec)) {
      throw Error(dataset.string() +
                  ": no annotations.json (give a generate output folder or a "
                  "COCO keypoint file)");
    }
    return {gt, o.images.empty() ? dataset / "images" : fs::path(o.images)};
  }
  if (!fs::is_regular_file(dataset, ec)) throw Error(o.dataset + ": no such dataset");
  if (o.images.empty()) throw Error(o.dataset + ": a COCO file needs --images (its photos)");
  return {dataset, fs::path(o.images)};
}

// The model's people in every image that holds someone to judge, as COCO results.
json predict_judged_images(const RealismCommandOptions& o, const json& root,
                           const coco::CocoGroundTruth& gt, const fs::path& images_dir) {
  std::map<std::int64_t, std::vector<coco::Box>> judged_boxes;
  const eval::ImageSizes sizes = eval::image_sizes(root);
  for (const coco::GtAnnotation& a : gt.annotations) {
    if (eval::realism_judges(a, o.realism, sizes)) judged_boxes[a.image_id].push_back(a.bbox);
  }
  std::optional<fs::path> models_dir;
  if (!o.models.empty()) models_dir = fs::path(o.models);
  const learn::ModelChoice choice = learn::choose_model(o.model, models_dir);
  const learn::PosePredictor predictor(
      choice.topology, learn::PredictOptions{.longer_sides = o.sizes, .threads = o.threads},
      choice.weights);
  if (o.realism.boxes && !predictor.multi_person()) {
    // A single-person model runs on crops around the labelled boxes: its box is not a finding.
    throw Error("--model " + o.model + ": --boxes needs a multi-person model");
  }
  spdlog::info(
      "realism: {} on {} images ({})", o.model, judged_boxes.size(),
      predictor.multi_person() ? "whole images" : "crops around the judged people's boxes");
  json results = json::array();
  Progress progress("realism", "images");
  std::int64_t done = 0;
  for (const coco::GtImage& image : gt.images) {
    const auto boxes = judged_boxes.find(image.id);
    if (boxes == judged_boxes.end()) continue;
    cv::Mat rgb;
    cv::cvtColor(read_image(images_dir / image.file_name, cv::IMREAD_COLOR), rgb,
                 cv::COLOR_BGR2RGB);
    const std::vector<learn::PosePrediction> people =
        predictor.multi_person() ? predictor.predict_image(rgb)
                                 : predictor.predict_boxes(rgb, boxes->second);
    for (const learn::PosePrediction& p : people) {
      results.push_back(learn::coco_result_json(image.id, p));
    }
    progress(++done, static_cast<std::int64_t>(judged_boxes.size()));
  }
  return results;
}

void run_realism(const RealismCommandOptions& o) {
  const auto [gt_path, images_dir] = dataset_files(o);
  const fs::path out(o.out);
  if (!o.out.empty()) {
    ensure_directory(out);
    check_output_file(out / "realism.json");
  }
  const json root = coco::parse_json_file(gt_path);
  const coco::CocoGroundTruth gt =
      coco::parse_coco_gt(root, gt_path.string(), 17, /*need_keypoints=*/!o.realism.boxes);
  json results;
  if (!o.dt.empty()) {
    results = coco::parse_json_file(o.dt);
  } else {
    results = predict_judged_images(o, root, gt, images_dir);
    if (!o.out.empty()) write_file_atomic(out / "results.json", results.dump() + "\n");
  }
  const coco::CocoResults dt =
      coco::parse_coco_results(results, o.dt.empty() ? o.model : o.dt, gt, 17);
  const eval::RealismReport report =
      eval::measure_realism(root, gt, dt, load_keypoint_template("coco17"), o.realism);
  const std::string title = gt_path.string() + " seen by " + (o.dt.empty() ? o.model : o.dt);
  const std::string markdown = eval::realism_markdown(report, title);
  std::fputs(markdown.c_str(), stdout);
  if (!o.out.empty()) {
    json doc = eval::realism_json(report, o.realism);
    doc["dataset"] = gt_path.string();
    doc["model"] = o.dt.empty() ? o.model : "";
    doc["results"] = o.dt.empty() ? (out / "results.json").string() : o.dt;
    write_file_atomic(out / "realism.md", markdown);
    write_file_atomic(out / "realism.json", doc.dump(2) + "\n");
  }
  spdlog::info("realism: {} people judged, {:.1f} % found, mean {} {:.3f}", report.overall.people,
               100 * report.overall.found_share(), o.realism.boxes ? "box IoU" : "OKS",
               report.overall.mean_oks());
}

}  // namespace

void attach_realism(CLI::App& parent) {
  auto o = std::make_shared<RealismCommandOptions>();
  CLI::App* cmd = parent.add_subcommand(
      "realism",
      "How a model trained on real photos sees a dataset's people: the share it finds (best "
      "match OKS >= 0.5, or box IoU with --boxes) and how close, overall and by every recorded "
      "attribute");
  cmd->add_option("dataset", o->dataset,
                  "A generate output folder (annotations.json, images/) or a COCO keypoint file")
      ->required();
  cmd->add_option("--images", o->images, "The images folder (default: DATASET/images)");
  cmd->add_option("--model", o->model,
                  "The real-photo model (a name, TF.js .json or .pt); single-person models run "
                  "on crops around the judged people's boxes")
      ->capture_default_str();
  cmd->add_option("--models", o->models, "Folder of the models (as for predict)");
  cmd->add_option("--size", o->sizes, "Multipose input sizes (as for predict)")
      ->delimiter(',')
      ->check(input_side())
      ->capture_default_str();
  cmd->add_option("--dt", o->dt, "Judge these COCO results instead of running --model");
  cmd->add_option("--out", o->out, "Folder for realism.md, realism.json (and results.json)");
  cmd->add_option("--min-height", o->realism.min_height_px, "Judge people at least this tall (px)")
      ->check(number_from(1, 1e6))
      ->capture_default_str();
  cmd->add_option("--min-keypoints", o->realism.min_keypoints,
                  "Judge people with at least this many labelled keypoints")
      ->check(CLI::Range(1, 17))
      ->capture_default_str();
  cmd->add_option("--min-visible", o->realism.min_visible_keypoints,
                  "Judge people with at least this many keypoints labelled visible (v = 2): "
                  "compares renders, which label hidden joints, with photos at equal visibility")
      ->check(CLI::Range(0, 17))
      ->capture_default_str();
  cmd->add_flag("--boxes", o->realism.boxes,
                "Judge by box: found where the model's best box has IoU >= 0.5 (any score); "
                "keypoint counts are not asked for, so a set labelled by box only is a reference");
  cmd->add_flag("--in-frame", o->realism.whole_in_frame,
                "Judge only people whose box does not touch the image border");
  cmd->add_option("--threads", o->threads, "Threads (0 = every core)")
      ->check(CLI::NonNegativeNumber);
  cmd->callback([o] { run_realism(*o); });
}

}  // namespace wheelpose::app
