#pragma once
// COCOeval (pycocotools) for keypoints and boxes: evaluate() matches per image, accumulate()
// builds the 101-point interpolated precision, summarize() gives the standard stats and text.
// Matching is done one image at a time, so memory grows with the input, not with its square.

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/coco_data.h"
#include "core/keypoint_template.h"

namespace wheelpose::eval {

struct EvalParams {
  coco::IouType type = coco::IouType::kKeypoints;
  std::vector<double> iou_thresholds;     // np.linspace(.5, .95, 10)
  std::vector<double> recall_thresholds;  // np.linspace(0, 1, 101)
  std::vector<int> max_dets;              // [20] or [1, 10, 100]
  std::vector<std::pair<double, double>> area_ranges;
  std::vector<std::string> area_labels;
  static EvalParams for_type(coco::IouType type);
};

// evaluateImg's result for one (category, area range, image); absent when neither GT nor
// detections exist there. Matrices are T x D / T x G, row-major by threshold.
struct ImageEval {
  std::vector<int> dt;  // detection indices, by descending score, <= maxDet
  std::vector<int> gt;  // annotation indices, non-ignored first
  std::vector<double> dt_scores;
  std::vector<std::int64_t> dt_matches;  // matched GT id, 0 = none (pycocotools' dtm)
  std::vector<int> dt_match_position;    // matched position in `gt`, -1 = none
  std::vector<std::uint8_t> dt_ignore;
  std::vector<int> gt_match_position;  // matched position in `dt`, -1 = none
  std::vector<std::uint8_t> gt_ignore;
};

struct StatLine {
  std::string key;  // e.g. "AP", "AP50", "ARm", "AR10"
  double value = -1;
};

struct EvalSummary {
  coco::IouType type = coco::IouType::kKeypoints;
  std::vector<StatLine> stats;
  std::string text;  // exactly as pycocotools' summarize() prints it

  // The stat named `key` ("AP", "AP50", ...); nullopt when it is not one of the summary's or
  // is pycocotools' −1 (nothing to score).
  std::optional<double> stat(const std::string& key) const;
};

class CocoEvaluator {
 public:
  // `keypoint_template` supplies the sigmas for keypoint OKS (ignored for boxes).
  CocoEvaluator(const coco::CocoGroundTruth& gt, const coco::CocoResults& dt, coco::IouType type,
                const KeypointTemplate& keypoint_template);

  void evaluate();
  // Precision and recall over every image, or over a resample of them: with `image_weights`
  // (one per ground-truth image, in its order) image i counts that many times, as a bootstrap
  // draws it.
  void accumulate(const std::vector<int>& image_weights = {});
  EvalSummary summarize() const;

  const EvalParams& params() const { return params_; }
  // Index: ((category * areas) + area) * images + image; nullptr when that image has nothing.
  const ImageEval* image_eval(int category, int area, int image) const;
  // precision[t][r][k][a][m] and recall[t][k][a][m], -1 where undefined.
  const std::vector<double>& precision() const { return precision_; }
  const std::vector<double>& recall() const { return recall_; }

 private:
  double summarize_one(bool ap, double iou_threshold, const std::string& area, int max_dets) const;

  const coco::CocoGroundTruth& gt_;
  const coco::CocoResults& dt_;
  EvalParams params_;
  std::vector<double> vars_;
  std::vector<ImageEval> evals_;
  std::vector<std::uint8_t> present_;
  std::vector<double> precision_;
  std::vector<double> recall_;
};

// Runs evaluate, accumulate and summarize.
EvalSummary run_coco_eval(const coco::CocoGroundTruth& gt, const coco::CocoResults& dt,
                          coco::IouType type, const KeypointTemplate& keypoint_template);

}  // namespace wheelpose::eval
