// `wheelpose predict`: a pretrained or fine-tuned MoveNet model run over a folder of images,
// written as COCO results JSON that `wheelpose eval` reads for keypoints and boxes.

#include <fmt/ranges.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <future>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <string>
#include <vector>

#include "app/cli_checks.h"
#include "core/allocator.h"
#include "core/atomic_file.h"
#include "core/coco_data.h"
#include "core/error.h"
#include "core/image_files.h"
#include "core/image_read.h"
#include "core/keypoint_template.h"
#include "eval/eval_viz.h"
#include "learn/model_ensemble.h"
#include "learn/model_files.h"
#include "learn/pose_predictor.h"
#include "progress.h"

namespace wheelpose::app {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

struct PredictCommandOptions {
  std::vector<std::string> model = {"movenet-multipose"};  // several: an ensemble
  std::string models;
  std::string coco;
  std::string images;
  std::string detections;
  std::string out;
  std::vector<int> sizes = {256, 640};
  double max_person_px = 192;
  double min_score = 0.05;
  bool flip = false;
  int threads = 0;
  std::string viz;
  int viz_count = 8;
  eval::VizPick viz_pick = eval::VizPick::kSpread;
};

struct ImageJob {
  std::int64_t id = 0;
  fs::path path;
  std::vector<coco::Box> boxes;  // single-person models: the people to crop
};

// The images to run: the COCO file's (ids from it) or every image file of the folder, sorted by
// name, with ids 1, 2, … in that order.
std::vector<ImageJob> list_images(const PredictCommandOptions& o,
                                  const std::optional<coco::CocoGroundTruth>& gt) {
  std::vector<ImageJob> jobs;
  const fs::path dir(o.images);
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw Error(o.images + ": --images is not a directory");
  if (gt) {
    for (const coco::GtImage& image : gt->images)
      jobs.push_back({image.id, dir / image.file_name, {}});
  } else {
    const std::vector<fs::path> files = image_files_in(dir);
    for (std::size_t i = 0; i < files.size(); ++i) {
      jobs.push_back({static_cast<std::int64_t>(i + 1), files[i], {}});
    }
  }
  if (jobs.empty()) {
    throw Error(o.images + ": no images to predict on (" +
                (gt ? o.coco + " lists none" : std::string("no .jpg, .jpeg, .png or .bmp files")) +
                ")");
  }
  return jobs;
}

// Single-person models: the boxes to crop, from a detections file (score ≥ 0.5) or the GT
// person annotations (not crowds).
void attach_boxes(const PredictCommandOptions& o, const std::optional<coco::CocoGroundTruth>& gt,
                  std::vector<ImageJob>& jobs) {
  std::map<std::int64_t, std::vector<coco::Box>> boxes;
  if (!o.detections.empty()) {
    if (!gt) throw Error("--detections needs --coco (its image ids)");
    const coco::CocoResults dets = coco::load_coco_results(o.detections, *gt, 17);
    for (const coco::Detection& d : dets.detections) {
      if (d.score >= 0.5) boxes[d.image_id].push_back(d.bbox);
    }
  } else if (gt) {
    for (const coco::GtAnnotation& a : gt->annotations) {
      if (!a.iscrowd) boxes[a.image_id].push_back(a.bbox);
    }
  } else {
    throw Error(o.model.front() +
                " is a single-person model: give --coco (its person boxes are cropped) or "
                "--detections");
  }
  for (ImageJob& job : jobs) job.boxes = boxes[job.id];
}

cv::Mat read_rgb(const fs::path& path) {
  cv::Mat bgr = read_image(path, cv::IMREAD_COLOR);
  cv::Mat rgb;
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  return rgb;
}

void run_predict(const PredictCommandOptions& o) {
  check_output_file(o.out);  // before minutes of work, not after
  std::vector<int> sizes = o.sizes;
  for (const int size : sizes) {
    if (size < 32 || size > learn::kMaxInputSide || size % 32 != 0) {
      throw Error("--size " + std::to_string(size) + ": must be a multiple of 32 from 32 to " +
                  std::to_string(learn::kMaxInputSide));
    }
  }
  std::sort(sizes.begin(), sizes.end());
  if (sizes.empty() || std::adjacent_find(sizes.begin(), sizes.end()) != sizes.end()) {
    throw Error("--size: give one or more different sizes, e.g. 256,640");
  }
  if (!o.viz.empty() && o.coco.empty()) throw Error("--viz needs --coco (the overlays draw GT)");
  std::optional<fs::path> models_dir;
  if (!o.models.empty()) models_dir = fs::path(o.models);
  std::optional<coco::CocoGroundTruth> gt;
  if (!o.coco.empty()) gt = coco::load_coco_gt(o.coco, 17, false);
  std::vector<ImageJob> jobs = list_images(o, gt);
  retain_large_blocks();  // multipose's per-image activations exceed 32 MiB at 512 px and above
  std::vector<std::unique_ptr<learn::PosePredictor>> predictors;
  std::vector<std::string> names;
  for (const std::string& name : o.model) {
    const learn::ModelChoice choice = learn::choose_model(name, models_dir);
    predictors.push_back(std::make_unique<learn::PosePredictor>(
        choice.topology,
        learn::PredictOptions{.longer_sides = sizes,
                              .max_person_px = o.max_person_px,
                              .min_score = o.min_score,
                              .threads = o.threads},
        choice.weights));
    names.push_back(choice.weights ? choice.weights->filename().string()
                                   : choice.topology.stem().string());
    if (predictors.size() > 1 && !predictors.back()->multi_person()) {
      throw Error("--model " + name + ": only multipose models make an ensemble");
    }
  }
  const learn::PosePredictor& first = *predictors.front();
  if (predictors.size() > 1 && !first.multi_person()) {
    throw Error("--model " + o.model.front() + ": only multipose models make an ensemble");
  }
  if (o.flip && !first.multi_person()) {
    throw Error("--flip: " + o.model.front() + " is a single-person model (multipose only)");
  }
  if (!first.multi_person()) attach_boxes(o, gt, jobs);
  spdlog::info("predict: {} on {} images ({})", fmt::join(names, " + "), jobs.size(),
               first.multi_person()
                   ? "whole images, longer side " + fmt::format("{}", fmt::join(sizes, " and "))
                   : std::to_string(first.crop_size()) + "² crops around person boxes");

  const KeypointTemplate coco17 = load_keypoint_template("coco17");
  json results = json::array();
  Progress progress("predict", "images");
  // The next image decodes on another thread while the model runs on this one.
  std::future<cv::Mat> next = std::async(std::launch::async, read_rgb, jobs[0].path);
  for (std::size_t i = 0; i < jobs.size(); ++i) {
    const cv::Mat rgb = next.get();
    if (i + 1 < jobs.size()) next = std::async(std::launch::async, read_rgb, jobs[i + 1].path);
    std::vector<learn::PosePrediction> people;
    if (!first.multi_person()) {
      people = first.predict_boxes(rgb, jobs[i].boxes);
    } else if (predictors.size() == 1 && !o.flip) {
      people = first.predict_image(rgb);
    } else {
      cv::Mat mirrored;
      if (o.flip) cv::flip(rgb, mirrored, 1);
      std::vector<std::vector<learn::PosePrediction>> views;
      for (const auto& predictor : predictors) {
        views.push_back(predictor->predict_image(rgb));
        if (!o.flip) continue;
        std::vector<learn::PosePrediction>& back = views.emplace_back();
        for (const learn::PosePrediction& p : predictor->predict_image(mirrored))
          back.push_back(learn::mirror_prediction(p, rgb.cols, coco17.flip_pairs));
      }
      people = learn::fuse_models(views, {});
    }
    for (const learn::PosePrediction& p : people)
      results.push_back(learn::coco_result_json(jobs[i].id, p));
    progress(static_cast<std::int64_t>(i + 1), static_cast<std::int64_t>(jobs.size()));
  }
  write_file_atomic(o.out, results.dump() + "\n");
  spdlog::info("predict: {} people in {} images -> {}", results.size(), jobs.size(), o.out);

  if (!o.viz.empty()) {
    const coco::CocoResults ours = coco::load_coco_results(o.out, *gt, coco17.size());
    const auto written = eval::write_overlays(*gt, ours, nullptr, coco17,
                                              {.count = o.viz_count,
                                               .pick = o.viz_pick,
                                               .images_dir = o.images,
                                               .out_dir = o.viz,
                                               .min_score = 0.3});
    spdlog::info("predict: {} overlays in {}", written.size(), o.viz);
  }
}

}  // namespace

void attach_predict(CLI::App& parent) {
  auto options = std::make_shared<PredictCommandOptions>();
  CLI::App* cmd = parent.add_subcommand(
      "predict", "Run a pretrained MoveNet pose model on images; write COCO results JSON");
  cmd->add_option(
         "--model", options->model,
         "movenet-multipose, movenet-lightning, movenet-thunder, a TF.js .json path, or a .pt "
         "from wheelpose train; several (multipose) make an ensemble whose people are fused "
         "(scores averaged, boxes and keypoints score-weighted)")
      ->capture_default_str();
  cmd->add_option("--models", options->models,
                  "Folder of the models (default: $WHEELPOSE_MODELS, ./models, the checkout's)");
  cmd->add_option("--images", options->images, "Folder of the images")->required();
  cmd->add_option("--coco", options->coco,
                  "COCO file naming the images (ids, and person boxes for single-person models)");
  cmd->add_option("--detections", options->detections,
                  "COCO results whose boxes (score >= 0.5) single-person models crop");
  cmd->add_option("--out", options->out, "COCO results JSON to write")->required();
  cmd->add_option("--size", options->sizes,
                  "Multipose input: the image's longer side (x32); several, comma-separated, run "
                  "the image at each and merge the people (default 256,640: real photos' large "
                  "people and our frames' small ones)")
      ->delimiter(',')
      ->check(input_side())
      ->capture_default_str();
  cmd->add_option("--max-person-px", options->max_person_px,
                  "Several sizes: people whose box is longer than this in a size's input are "
                  "left to the smaller sizes")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--min-score", options->min_score, "Multipose: drop people scoring less")
      ->check(number_from(0, 1))
      ->capture_default_str();
  cmd->add_flag("--flip", options->flip,
                "Multipose: also run each model on the mirrored image and fuse the two views "
                "like an ensemble's (test-time flip)");
  cmd->add_option("--threads", options->threads, "Threads (0 = every core)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--viz", options->viz, "Write overlays of GT and predictions into this folder");
  cmd->add_option("--viz-pick", options->viz_pick,
                  "Which images --viz draws: spread (evenly spaced), best or worst (by mean OKS)")
      ->transform(CLI::CheckedTransformer(eval::viz_pick_names()));
  cmd->add_option("--viz-count", options->viz_count, "How many overlays")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->callback([options] { run_predict(*options); });
}

}  // namespace wheelpose::app
