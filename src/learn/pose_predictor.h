#pragma once
// A pretrained (or fine-tuned) MoveNet model run on images: people with COCO-17 keypoints in
// image pixels. Torch-free: the LibTorch graph lives behind Impl.
//
// movenet-multipose sees the whole image (learn/letterbox.h) and decodes up to 6 people with
// its own graph (output 1×6×56: 17 × (y, x, score), box ymin, xmin, ymax, xmax, score, all as
// fractions of the input). movenet-lightning (192) and movenet-thunder (256) see one person:
// a square crop around each given box (output 1×1×17×3).

#include <array>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "core/coco_data.h"

namespace wheelpose::learn {

struct PosePrediction {
  std::array<double, 51> keypoints{};  // x, y in pixels and the keypoint score, COCO-17 order
  double score = 0;                    // multipose: the person score; single: mean keypoint score
  coco::Box bbox;                      // multipose: the model's box; single: the given box
};

// The largest multipose input side: the width of the frames we render. Beyond it the network's
// quarter-resolution heatmaps see people larger than any it learned, while time and memory grow
// with the square (4096 took 6 GB and 11 s an image).
inline constexpr int kMaxInputSide = 1280;

struct PredictOptions {
  // Multipose inputs: the image's longer side, multiples of 32, smallest first. Several sizes
  // run the image at each and merge the people (learn/scale_merge.h): 256 serves people who
  // fill a photo, 640 the small people of wide frames; neither alone serves both.
  std::vector<int> longer_sides = {256, 640};
  double max_person_px = 192;  // several sizes: larger people are left to the smaller size
  double min_score = 0.05;     // multipose: people scoring less are dropped
  int threads = 0;             // intra-op threads; 0 = every core
};

// One COCO result entry (image_id, category 1, keypoints, score, bbox), rounded to 0.01 px and
// 1e-4 in score: what `predict` writes and the evaluator reads, so in-memory scoring during
// training sees exactly the numbers a written file would hold.
nlohmann::json coco_result_json(std::int64_t image_id, const PosePrediction& prediction);

class PosePredictor {
 public:
  // `model_json`: a TF.js MoveNet topology. Throws Error for a file that does not load or a
  // model whose output is not MoveNet's.
  // `weights`: a fine-tuned .pt of the same model to load (GraphModule::save).
  PosePredictor(const std::filesystem::path& model_json, const PredictOptions& options,
                const std::optional<std::filesystem::path>& weights = std::nullopt);
  ~PosePredictor();
  PosePredictor(const PosePredictor&) = delete;
  PosePredictor& operator=(const PosePredictor&) = delete;

  bool multi_person() const;
  int crop_size() const;  // single-person models' input side

  // Multipose: the people in `rgb` (CV_8UC3, RGB).
  std::vector<PosePrediction> predict_image(const cv::Mat& rgb) const;
  // Single-person: one prediction per box.
  std::vector<PosePrediction> predict_boxes(const cv::Mat& rgb,
                                            const std::vector<coco::Box>& boxes) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace wheelpose::learn
