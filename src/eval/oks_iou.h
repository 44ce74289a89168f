#pragma once
// Similarity between one detection and one ground truth, bit-for-bit as pycocotools computes it:
// COCOeval.computeOks (keypoints) and maskApi.c bbIou (boxes).

#include <cstddef>
#include <span>
#include <vector>

#include "core/coco_data.h"
#include "core/keypoint_template.h"

namespace wheelpose::eval {

// Sum in numpy's pairwise order (np.sum / np.mean on a contiguous float64 array), so means match
// pycocotools to the last bit.
double numpy_sum(const double* values, std::size_t n);

// vars_i = (2 sigma_i)^2, the kappa^2 of the OKS formula.
std::vector<double> oks_vars(const KeypointTemplate& keypoint_template);

// e_i = d_i^2 / vars_i / (area + eps) / 2, the exponent of one keypoint's OKS term.
double oks_exponent(double dx, double dy, double var, double area);

// OKS of detection keypoints `dt` (x, y, score triples) against `gt`. A GT without labelled
// keypoints measures distance to its box grown by its own size, averaged over all keypoints.
double compute_oks(const coco::GtAnnotation& gt, std::span<const double> dt,
                   std::span<const double> vars);

// IoU of two [x, y, w, h] boxes; for a crowd GT the union is the detection's area.
double bbox_iou(const coco::Box& dt, const coco::Box& gt, bool gt_is_crowd);

}  // namespace wheelpose::eval
