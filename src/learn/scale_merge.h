#pragma once
// Multi-scale inference for MoveNet MultiPose: the image is run at several input sizes (its
// longer side, as `predict --size`) and the people found are merged. Each size is trusted for
// the people it sees at a size the network was trained on: a person whose box is larger than
// `max_person_px` in a size's input is left to a smaller size (the largest real photos'
// people overflow the network's receptive field at 640 and it finds parts of them), and one
// smaller than `min_person_px` is left to a larger size (too few pixels to find joints). The
// people left are merged by greedy non-maximum suppression on the score. Torch-free.

#include <vector>

#include "learn/pose_predictor.h"

namespace wheelpose::learn {

struct ScaleMergeOptions {
  double max_person_px = 256;  // the longer box side, in that size's input pixels
  double min_person_px = 0;
  double iou = 0.5;          // boxes overlapping more are the same person
  double containment = 1.0;  // or the smaller box lies this much inside the other (1: off)
};

struct ScaleResult {
  double input_per_image_px = 1;  // the size's letterbox scale
  std::vector<PosePrediction> people;
};

// `scales` ordered from the smallest input to the largest. The smallest keeps its large
// people and the largest its small ones, so no one is dropped for lack of a size. The result is
// ordered by score, highest first (ties: smaller scale first, then the model's order).
std::vector<PosePrediction> merge_scales(const std::vector<ScaleResult>& scales,
                                         const ScaleMergeOptions& options);

}  // namespace wheelpose::learn
