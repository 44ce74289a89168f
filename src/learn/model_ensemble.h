#pragma once
// Several models' people in one image fused into one list (weighted boxes fusion, Solovyev et
// al. 2019, extended to keypoints). Used by `predict --model A --model B`: the pretrained model
// keeps its judgement of real people and backgrounds, the fine-tuned one adds what it learned
// of wheelchair users, and a person found by one model alone keeps only its share of the score.
//
// People of all models, highest score first, join the first group whose leading (highest
// scoring) person overlaps theirs by IoU ≥ `iou` and that holds no one from their model yet;
// otherwise they lead a new group. A group becomes one person:
//   score     = Σ_m weight_m × score_m            (a model with no one in the group adds 0)
//   box       = score-weighted mean of the members' boxes
//   keypoint  = mean of the members' positions weighted by score × keypoint score, and
//               Σ_m weight_m × keypoint score_m as its score
// `predict --flip` adds each model's view of the mirrored image as one more member
// (`mirror_prediction` maps it back), the test-time flip of pose estimation. Torch-free.

#include <utility>
#include <vector>

#include "learn/pose_predictor.h"

namespace wheelpose::learn {

struct EnsembleOptions {
  double iou = 0.5;
  std::vector<double> weights;  // one per model; empty: equal weights summing to 1
};

// `per_model[m]`: model m's people in the image. The result is ordered by fused score, highest
// first (ties: the order the groups were made in). Throws Error for weights of the wrong count.
std::vector<PosePrediction> fuse_models(const std::vector<std::vector<PosePrediction>>& per_model,
                                        const EnsembleOptions& options);

// A person found in the left-right mirror of an image `image_width` pixels wide, in the image's
// own coordinates: x → image_width − x (continuous pixel coordinates), the box mirrored, and
// each pair of `flip_pairs` (0-based COCO-17 indices, e.g. left and right wrist) swapped.
PosePrediction mirror_prediction(const PosePrediction& person, double image_width,
                                 const std::vector<std::pair<int, int>>& flip_pairs);

}  // namespace wheelpose::learn
