#include "learn/scale_merge.h"

#include <algorithm>

namespace wheelpose::learn {
namespace {

struct Overlap {
  double iou = 0;
  double containment = 0;  // intersection over the smaller box's area
};

Overlap overlap(const coco::Box& a, const coco::Box& b) {
  const double iw = std::max(0.0, std::min(a.x + a.w, b.x + b.w) - std::max(a.x, b.x));
  const double ih = std::max(0.0, std::min(a.y + a.h, b.y + b.h) - std::max(a.y, b.y));
  const double inter = iw * ih;
  const double area_a = a.w * a.h, area_b = b.w * b.h;
  const double uni = area_a + area_b - inter;
  const double smaller = std::min(area_a, area_b);
  return {uni > 0 ? inter / uni : 0.0, smaller > 0 ? inter / smaller : 0.0};
}

}  // namespace

std::vector<PosePrediction> merge_scales(const std::vector<ScaleResult>& scales,
                                         const ScaleMergeOptions& o) {
  std::vector<PosePrediction> candidates;
  for (std::size_t i = 0; i < scales.size(); ++i) {
    const bool smallest = i == 0, largest = i + 1 == scales.size();
    for (const PosePrediction& p : scales[i].people) {
      const double side = std::max(p.bbox.w, p.bbox.h) * scales[i].input_per_image_px;
      if (!smallest && side > o.max_person_px) continue;
      if (!largest && side < o.min_person_px) continue;
      candidates.push_back(p);
    }
  }
  // Stable: equal scores keep the smaller scale's person, then the model's order.
  std::stable_sort(
      candidates.begin(), candidates.end(),
      [](const PosePrediction& a, const PosePrediction& b) { return a.score > b.score; });
  std::vector<PosePrediction> kept;
  for (const PosePrediction& p : candidates) {
    const bool duplicate = std::any_of(kept.begin(), kept.end(), [&](const PosePrediction& k) {
      const Overlap v = overlap(p.bbox, k.bbox);
      return v.iou > o.iou || (o.containment < 1 && v.containment > o.containment);
    });
    if (!duplicate) kept.push_back(p);
  }
  return kept;
}

}  // namespace wheelpose::learn
