#pragma once
// The paper's per-keypoint metrics (Table 6), defined on the COCO matching instead of the
// authors' all-pairs loops: a pair is a non-ignored GT person and the detection COCOeval matched
// to it at OKS >= 0.5 (area "all", maxDets 20, same image). Only GT keypoints with v > 0 count.
//   PDJ@5  fraction of keypoints with error < 5% of the GT box diagonal
//   PJPE   mean pixel error
//   OKS50 / OKS75  fraction of keypoints whose OKS term exp(-d^2 / (2 s^2 k^2)) (s^2 = GT area,
//          k = 2 sigma) is > 0.5 / > 0.75
//   missed GT people never matched, and their labelled keypoints per keypoint

#include <optional>
#include <string>
#include <vector>

#include "eval/coco_eval.h"

namespace wheelpose::eval {

struct KeypointStats {
  std::string name;
  long count = 0;   // labelled keypoints in matched pairs
  long missed = 0;  // labelled keypoints of GT people never matched
  // nullopt when count == 0.
  std::optional<double> pdj5, pjpe, oks50, oks75;
};

struct KeypointMetrics {
  long gt_people = 0;      // non-ignored GT people
  long pairs = 0;          // matched at OKS >= 0.5
  long missed_people = 0;  // gt_people - pairs
  KeypointStats overall;
  std::vector<KeypointStats> keypoints;  // template order
  std::vector<KeypointStats> groups;     // template groups, pooled over their keypoints
};

// `evaluator` must be a keypoint evaluator on which evaluate() has run.
KeypointMetrics compute_keypoint_metrics(const CocoEvaluator& evaluator,
                                         const coco::CocoGroundTruth& gt,
                                         const coco::CocoResults& dt,
                                         const KeypointTemplate& keypoint_template);

// Every non-ignored GT person as (annotation index, matched detection index or -1), by image.
std::vector<std::pair<int, int>> matched_pairs(const CocoEvaluator& evaluator,
                                               const coco::CocoGroundTruth& gt);

}  // namespace wheelpose::eval
