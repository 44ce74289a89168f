#pragma once
// Training targets for MoveNet MultiPose's six heads (a CenterNet at stride 4), built from the
// people of one augmented sample. Torch-free: dense heatmaps and sparse regression entries that
// the trainer turns into tensors. How each target is built (docs/ARCHITECTURE.md, learn):
//  - grid coordinates are input pixels / 4; the head cell of a point is its floor;
//  - centre heatmap: a Gaussian (peak 1 at the box centre's cell) per person, max-merged;
//  - keypoint heatmaps: the same Gaussian at each labelled keypoint's cell (v = 1 or 2);
//  - at the centre cell: keypoint regression = keypoint − centre cell (y, x per keypoint,
//    labelled ones only), box scale = (h, w), box offset = box centre − centre cell;
//  - at each labelled keypoint's cell: offset = keypoint − cell (y, x), weight 1; with an
//    offset radius R > 0 also at every cell within R cells (Chebyshev) of it, weighted by the
//    Gaussian below at that cell, so the offsets form a field that points at the keypoint from
//    wherever the decoder's heatmap peak lands (the pretrained MultiPose's field does: its
//    offsets one cell away miss the keypoint by 0.22 cells on real photos, and one-cell targets
//    let fine-tuning wreck that to 0.77). A cell near two people's same keypoint takes the
//    heavier one;
//  - crowd regions get no targets; their cells get heatmap weight 0 (no negative loss there).
// Sigma of the Gaussians, in cells: max(0.8, 0.1 · sqrt(box h · box w)) — the spread grows with
// the person so a large person's peak is not a single cell.

#include <array>
#include <vector>

#include "learn/train_data.h"

namespace wheelpose::learn {

inline constexpr int kOutputStride = 4;
inline constexpr int kKeypoints = 17;

struct CentreTarget {
  int cell = 0;                                  // y * grid + x
  std::array<float, 2 * kKeypoints> regress{};   // (dy, dx) per keypoint
  std::array<float, kKeypoints> regress_mask{};  // 1 where labelled
  std::array<float, 2> scale{};                  // (h, w) in cells
  std::array<float, 2> offset{};                 // (dy, dx)
};

struct KeypointTarget {
  int cell = 0;
  int keypoint = 0;
  std::array<float, 2> offset{};  // (dy, dx)
  float weight = 1;               // 1 at the keypoint's own cell, the Gaussian around it
};

struct MovenetTargets {
  int grid = 0;                         // cells per side (input_size / 4)
  std::vector<float> centre_heatmap;    // grid × grid
  std::vector<float> keypoint_heatmap;  // grid × grid × 17 (NHWC, as the head)
  // grid × grid: 0 in the cells of crowd regions (TrainPerson::ignore) that no person's centre
  // Gaussian reaches, 1 elsewhere; empty when the sample has no crowd region.
  std::vector<float> heatmap_weight;
  std::vector<CentreTarget> centres;
  std::vector<KeypointTarget> keypoints;
};

// `offset_radius`: cells around each keypoint's cell that get offset targets too (0: its own
// cell only, CenterNet's rule).
MovenetTargets build_targets(const std::vector<TrainPerson>& people, int input_size,
                             int offset_radius = 0);

}  // namespace wheelpose::learn
