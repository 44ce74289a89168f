#pragma once
// Scoring a model on a COCO keypoint file while it trains: `predict` (multipose, whole images)
// and `eval` (pycocotools' keypoint and box AP) in memory, with the same rounding a written
// results file has, so the numbers equal `wheelpose predict` + `wheelpose eval` on that file.
// Torch-free.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/coco_data.h"

namespace wheelpose::learn {

struct ValidationScores {
  double keypoint_ap = 0, keypoint_ap50 = 0, keypoint_ar = 0;
  double box_ap = 0, box_ap50 = 0;
  int detections = 0;
};

class Validator {
 public:
  // Reads the ground truth (images in images/ beside it or beside the file, as for --train).
  // Throws Error naming the file for an invalid COCO file or a missing image.
  // `threads`: intra-op threads while scoring, 0 = every core.
  Validator(const std::filesystem::path& coco, int longer_side, int threads = 0);

  // Runs the model (topology + optional fine-tuned weights) over every image and scores it.
  ValidationScores score(const std::filesystem::path& model_json,
                         const std::optional<std::filesystem::path>& weights) const;

  std::size_t image_count() const { return files_.size(); }

 private:
  std::filesystem::path coco_;
  coco::CocoGroundTruth gt_;
  std::vector<std::filesystem::path> files_;  // by gt_.images
  int longer_side_;
  int threads_;
};

}  // namespace wheelpose::learn
