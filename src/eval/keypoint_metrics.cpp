#include "eval/keypoint_metrics.h"

#include <cmath>

#include "core/error.h"
#include "eval/oks_iou.h"

namespace wheelpose::eval {
namespace {

struct Sums {
  long count = 0, missed = 0, pdj = 0, oks50 = 0, oks75 = 0;
  double error = 0;
  void add(const Sums& o) {
    count += o.count;
    missed += o.missed;
    pdj += o.pdj;
    oks50 += o.oks50;
    oks75 += o.oks75;
    error += o.error;
  }
};

KeypointStats finish(const std::string& name, const Sums& s) {
  KeypointStats k;
  k.name = name;
  k.count = s.count;
  k.missed = s.missed;
  if (s.count > 0) {
    const double n = static_cast<double>(s.count);
    k.pdj5 = s.pdj / n;
    k.pjpe = s.error / n;
    k.oks50 = s.oks50 / n;
    k.oks75 = s.oks75 / n;
  }
  return k;
}

}  // namespace

std::vector<std::pair<int, int>> matched_pairs(const CocoEvaluator& evaluator,
                                               const coco::CocoGroundTruth& gt) {
  if (evaluator.params().type != coco::IouType::kKeypoints) {
    throw Error("internal: keypoint metrics need the keypoint evaluation", ErrorKind::kFailure);
  }
  std::vector<std::pair<int, int>> pairs;
  const int area_all = 0, threshold_50 = 0;  // areaRng "all", iouThrs[0] = 0.5
  for (std::size_t k = 0; k < gt.category_ids.size(); ++k) {
    for (std::size_t i = 0; i < gt.images.size(); ++i) {
      const ImageEval* e = evaluator.image_eval(static_cast<int>(k), area_all, static_cast<int>(i));
      if (!e) continue;
      const std::size_t G = e->gt.size();
      for (std::size_t g = 0; g < G; ++g) {
        if (e->gt_ignore[g]) continue;
        const int d = e->gt_match_position[threshold_50 * G + g];
        pairs.emplace_back(e->gt[g], d < 0 ? -1 : e->dt[d]);
      }
    }
  }
  return pairs;
}

KeypointMetrics compute_keypoint_metrics(const CocoEvaluator& evaluator,
                                         const coco::CocoGroundTruth& gt,
                                         const coco::CocoResults& dt,
                                         const KeypointTemplate& keypoint_template) {
  const int K = keypoint_template.size();
  const std::vector<double> vars = oks_vars(keypoint_template);
  std::vector<Sums> per(K);
  KeypointMetrics m;
  for (const auto& [gi, di] : matched_pairs(evaluator, gt)) {
    const coco::GtAnnotation& g = gt.annotations[gi];
    ++m.gt_people;
    if (di < 0) {
      ++m.missed_people;
      for (int k = 0; k < K; ++k) per[k].missed += g.keypoints[3 * k + 2] > 0 ? 1 : 0;
      continue;
    }
    ++m.pairs;
    const coco::Detection& d = dt.detections[di];
    const double diagonal = std::sqrt(g.bbox.w * g.bbox.w + g.bbox.h * g.bbox.h);
    for (int k = 0; k < K; ++k) {
      if (!(g.keypoints[3 * k + 2] > 0)) continue;
      const double dx = d.keypoints[3 * k] - g.keypoints[3 * k];
      const double dy = d.keypoints[3 * k + 1] - g.keypoints[3 * k + 1];
      const double error = std::sqrt(dx * dx + dy * dy);
      const double term = std::exp(-oks_exponent(dx, dy, vars[k], g.area));
      Sums& s = per[k];
      ++s.count;
      s.error += error;
      s.pdj += error < 0.05 * diagonal ? 1 : 0;
      s.oks50 += term > 0.5 ? 1 : 0;
      s.oks75 += term > 0.75 ? 1 : 0;
    }
  }
  Sums all;
  for (int k = 0; k < K; ++k) {
    m.keypoints.push_back(finish(keypoint_template.keypoints[k].name, per[k]));
    all.add(per[k]);
  }
  m.overall = finish("all", all);
  for (const KeypointGroup& group : keypoint_template.groups) {
    Sums s;
    for (int k : group.indices) s.add(per[k]);
    m.groups.push_back(finish(group.name, s));
  }
  return m;
}

}  // namespace wheelpose::eval
