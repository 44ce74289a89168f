#include "learn/validation.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/error.h"
#include "core/image_read.h"
#include "core/keypoint_template.h"
#include "eval/coco_eval.h"
#include "learn/pose_predictor.h"
#include "learn/train_data.h"

namespace wheelpose::learn {
namespace {

namespace fs = std::filesystem;

double stat(const eval::EvalSummary& summary, const std::string& key) {
  return summary.stat(key).value_or(0.0);  // -1: nothing to score
}

}  // namespace

Validator::Validator(const fs::path& coco, int longer_side, int threads)
    : coco_(coco),
      gt_(coco::load_coco_gt(coco, 17, false)),
      longer_side_(longer_side),
      threads_(threads) {
  if (longer_side < 32 || longer_side > kMaxInputSide || longer_side % 32 != 0) {
    throw Error("--val-size " + std::to_string(longer_side) +
                ": must be a multiple of 32 from 32 to " + std::to_string(kMaxInputSide));
  }
  if (gt_.images.empty()) throw Error(coco.string() + ": no images to validate on");
  const fs::path root = image_root(coco);
  for (const coco::GtImage& image : gt_.images) {
    files_.push_back(root / image.file_name);
    if (!fs::is_regular_file(files_.back())) {
      throw Error(coco.string() + ": image " + files_.back().string() + " (id " +
                  std::to_string(image.id) + ") not found");
    }
  }
}

ValidationScores Validator::score(const fs::path& model_json,
                                  const std::optional<fs::path>& weights) const {
  PredictOptions options;
  options.longer_sides = {longer_side_};
  options.threads = threads_;
  const PosePredictor predictor(model_json, options, weights);
  nlohmann::json results = nlohmann::json::array();
  for (std::size_t i = 0; i < files_.size(); ++i) {
    const cv::Mat bgr = read_image(files_[i], cv::IMREAD_COLOR);
    cv::Mat rgb;
    cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
    for (const PosePrediction& p : predictor.predict_image(rgb)) {
      results.push_back(coco_result_json(gt_.images[i].id, p));
    }
  }
  ValidationScores scores;
  scores.detections = static_cast<int>(results.size());
  if (results.empty()) return scores;
  const coco::CocoResults dt = coco::parse_coco_results(results, "validation", gt_, 17);
  const KeypointTemplate coco17 = load_keypoint_template("coco17");
  const eval::EvalSummary keypoints =
      eval::run_coco_eval(gt_, dt, coco::IouType::kKeypoints, coco17);
  const eval::EvalSummary boxes = eval::run_coco_eval(gt_, dt, coco::IouType::kBbox, coco17);
  scores.keypoint_ap = stat(keypoints, "AP");
  scores.keypoint_ap50 = stat(keypoints, "AP50");
  scores.keypoint_ar = stat(keypoints, "AR");
  scores.box_ap = stat(boxes, "AP");
  scores.box_ap50 = stat(boxes, "AP50");
  return scores;
}

}  // namespace wheelpose::learn
