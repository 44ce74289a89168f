#include "eval/coco_eval.h"

#include <algorithm>
#include <cstdio>
#include <numeric>

#include "core/error.h"
#include "eval/oks_iou.h"

namespace wheelpose::eval {
namespace {

// np.linspace(start, stop, num): i * step + start, with the last value set to stop.
std::vector<double> linspace(double start, double stop, int num) {
  const double step = (stop - start) / (num - 1);
  std::vector<double> v(num);
  for (int i = 0; i < num; ++i) v[i] = static_cast<double>(i) * step + start;
  v[num - 1] = stop;
  return v;
}

// np.argsort(-scores, kind='mergesort'): descending score, ties keep input order.
void sort_by_score(std::vector<int>& order, const std::vector<coco::Detection>& dets) {
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return -dets[a].score < -dets[b].score; });
}

bool gt_ignored(const coco::GtAnnotation& g, coco::IouType type) {
  // _prepare: ignore = iscrowd; keypoints also ignore num_keypoints == 0 (the field).
  return g.iscrowd || (type == coco::IouType::kKeypoints && g.num_keypoints == 0);
}

}  // namespace

EvalParams EvalParams::for_type(coco::IouType type) {
  EvalParams p;
  p.type = type;
  p.iou_thresholds = linspace(0.5, 0.95, 10);
  p.recall_thresholds = linspace(0.0, 1.0, 101);
  const double big = 1e5 * 1e5;
  if (type == coco::IouType::kKeypoints) {
    p.max_dets = {20};
    p.area_ranges = {{0.0, big}, {32.0 * 32.0, 96.0 * 96.0}, {96.0 * 96.0, big}};
    p.area_labels = {"all", "medium", "large"};
  } else {
    p.max_dets = {1, 10, 100};
    p.area_ranges = {
        {0.0, big}, {0.0, 32.0 * 32.0}, {32.0 * 32.0, 96.0 * 96.0}, {96.0 * 96.0, big}};
    p.area_labels = {"all", "small", "medium", "large"};
  }
  return p;
}

CocoEvaluator::CocoEvaluator(const coco::CocoGroundTruth& gt, const coco::CocoResults& dt,
                             coco::IouType type, const KeypointTemplate& keypoint_template)
    : gt_(gt), dt_(dt), params_(EvalParams::for_type(type)), vars_(oks_vars(keypoint_template)) {}

const ImageEval* CocoEvaluator::image_eval(int category, int area, int image) const {
  const std::size_t index =
      (static_cast<std::size_t>(category) * params_.area_ranges.size() + area) * gt_.images.size() +
      image;
  if (index >= evals_.size() || !present_[index]) return nullptr;
  return &evals_[index];
}

void CocoEvaluator::evaluate() {
  const std::size_t num_images = gt_.images.size();
  const std::size_t num_cats = gt_.category_ids.size();
  const std::size_t num_areas = params_.area_ranges.size();
  const coco::IouType type = params_.type;
  const int max_det = params_.max_dets.back();
  const std::size_t T = params_.iou_thresholds.size();

  // Annotations and detections per (category, image), in file order (getAnnIds order).
  std::vector<std::vector<int>> gts(num_cats * num_images), dts(num_cats * num_images);
  for (std::size_t i = 0; i < gt_.annotations.size(); ++i) {
    const int img = gt_.image_position(gt_.annotations[i].image_id);
    const int cat = gt_.category_position(gt_.annotations[i].category_id);
    if (img >= 0 && cat >= 0) gts[cat * num_images + img].push_back(static_cast<int>(i));
  }
  for (std::size_t i = 0; i < dt_.detections.size(); ++i) {
    const int img = gt_.image_position(dt_.detections[i].image_id);
    const int cat = gt_.category_position(dt_.detections[i].category_id);
    if (img >= 0 && cat >= 0) dts[cat * num_images + img].push_back(static_cast<int>(i));
  }

  evals_.assign(num_cats * num_areas * num_images, ImageEval{});
  present_.assign(evals_.size(), 0);
  std::vector<double> ious;
  for (std::size_t k = 0; k < num_cats; ++k) {
    for (std::size_t img = 0; img < num_images; ++img) {
      const std::vector<int>& g = gts[k * num_images + img];
      std::vector<int>& d = dts[k * num_images + img];
      if (g.empty() && d.empty()) continue;
      sort_by_score(d, dt_.detections);
      if (d.size() > static_cast<std::size_t>(max_det)) d.resize(max_det);
      const std::size_t G = g.size(), D = d.size();
      // ious[d][g] over the original GT order, as computeIoU / computeOks return them.
      ious.assign(D * G, 0.0);
      for (std::size_t di = 0; di < D; ++di) {
        const coco::Detection& det = dt_.detections[d[di]];
        for (std::size_t gi = 0; gi < G; ++gi) {
          const coco::GtAnnotation& ann = gt_.annotations[g[gi]];
          ious[di * G + gi] = type == coco::IouType::kKeypoints
                                  ? compute_oks(ann, det.keypoints, vars_)
                                  : bbox_iou(det.bbox, ann.bbox, ann.iscrowd);
        }
      }
      for (std::size_t a = 0; a < num_areas; ++a) {
        const auto [lo, hi] = params_.area_ranges[a];
        const std::size_t index = (k * num_areas + a) * num_images + img;
        ImageEval& e = evals_[index];
        present_[index] = 1;
        // Non-ignored GTs first (stable), as evaluateImg's mergesort on _ignore.
        std::vector<std::uint8_t> ignore_raw(G);
        for (std::size_t gi = 0; gi < G; ++gi) {
          const coco::GtAnnotation& ann = gt_.annotations[g[gi]];
          ignore_raw[gi] = gt_ignored(ann, type) || ann.area < lo || ann.area > hi;
        }
        std::vector<int> gt_order(G);
        std::iota(gt_order.begin(), gt_order.end(), 0);
        std::stable_sort(gt_order.begin(), gt_order.end(),
                         [&](int x, int y) { return ignore_raw[x] < ignore_raw[y]; });
        e.gt.resize(G);
        e.gt_ignore.resize(G);
        for (std::size_t gi = 0; gi < G; ++gi) {
          e.gt[gi] = g[gt_order[gi]];
          e.gt_ignore[gi] = ignore_raw[gt_order[gi]];
        }
        e.dt = d;
        e.dt_scores.resize(D);
        for (std::size_t di = 0; di < D; ++di) e.dt_scores[di] = dt_.detections[d[di]].score;
        e.dt_matches.assign(T * D, 0);
        e.dt_match_position.assign(T * D, -1);
        e.dt_ignore.assign(T * D, 0);
        e.gt_match_position.assign(T * G, -1);
        std::vector<std::int64_t> gtm(T * G, 0);  // matched detection id, 0 = none
        if (G > 0 && D > 0) {
          for (std::size_t t = 0; t < T; ++t) {
            for (std::size_t di = 0; di < D; ++di) {
              double iou = std::min(params_.iou_thresholds[t], 1 - 1e-10);
              int m = -1;
              for (std::size_t gi = 0; gi < G; ++gi) {
                const bool crowd = gt_.annotations[e.gt[gi]].iscrowd;
                // pycocotools tests gtm > 0: detection ids start at 1, so this is "matched".
                if (gtm[t * G + gi] > 0 && !crowd) continue;
                // Stop at the first ignored GT once a regular GT is matched.
                if (m > -1 && e.gt_ignore[m] == 0 && e.gt_ignore[gi] == 1) break;
                const double v = ious[di * G + gt_order[gi]];
                if (v < iou) continue;
                iou = v;
                m = static_cast<int>(gi);
              }
              if (m == -1) continue;
              e.dt_ignore[t * D + di] = e.gt_ignore[m];
              e.dt_matches[t * D + di] = gt_.annotations[e.gt[m]].id;
              e.dt_match_position[t * D + di] = m;
              gtm[t * G + m] = dt_.detections[d[di]].id;
              e.gt_match_position[t * G + m] = static_cast<int>(di);
            }
          }
        }
        // Unmatched detections outside the area range are ignored. "Unmatched" is dtm == 0,
        // so a match to a GT with id 0 counts as unmatched here, exactly as in pycocotools.
        for (std::size_t di = 0; di < D; ++di) {
          const double da = dt_.detections[d[di]].area;
          const bool outside = da < lo || da > hi;
          for (std::size_t t = 0; t < T; ++t) {
            if (outside && e.dt_matches[t * D + di] == 0) e.dt_ignore[t * D + di] = 1;
          }
        }
      }
    }
  }
}

void CocoEvaluator::accumulate(const std::vector<int>& image_weights) {
  const std::size_t T = params_.iou_thresholds.size();
  const std::size_t R = params_.recall_thresholds.size();
  const std::size_t K = gt_.category_ids.size();
  const std::size_t A = params_.area_ranges.size();
  const std::size_t M = params_.max_dets.size();
  const std::size_t I = gt_.images.size();
  if (!image_weights.empty() && image_weights.size() != I) {
    throw Error("internal: accumulate() got " + std::to_string(image_weights.size()) +
                    " image weights for " + std::to_string(I) + " images",
                ErrorKind::kFailure);
  }
  precision_.assign(T * R * K * A * M, -1.0);
  recall_.assign(T * K * A * M, -1.0);
  constexpr double kEps = 2.220446049250313e-16;  // np.spacing(1)

  std::vector<double> scores;
  std::vector<int> order;
  std::vector<std::int64_t> dtm;
  std::vector<std::uint8_t> dtig;
  std::vector<double> rc, pr;
  for (std::size_t k = 0; k < K; ++k) {
    for (std::size_t a = 0; a < A; ++a) {
      for (std::size_t m = 0; m < M; ++m) {
        const std::size_t max_det = params_.max_dets[m];
        // Concatenate the top max_det detections of every image, then sort by score.
        scores.clear();
        std::vector<const ImageEval*> used;
        std::size_t npig = 0;
        for (std::size_t i = 0; i < I; ++i) {
          const std::size_t index = (k * A + a) * I + i;
          if (!present_[index]) continue;
          const ImageEval& e = evals_[index];
          const int copies = image_weights.empty() ? 1 : image_weights[i];
          for (int copy = 0; copy < copies; ++copy) {
            used.push_back(&e);
            const std::size_t n = std::min(max_det, e.dt.size());
            scores.insert(scores.end(), e.dt_scores.begin(), e.dt_scores.begin() + n);
            for (auto ig : e.gt_ignore) npig += ig == 0 ? 1 : 0;
          }
        }
        if (used.empty() || npig == 0) continue;
        const std::size_t nd = scores.size();
        order.resize(nd);
        std::iota(order.begin(), order.end(), 0);
        std::stable_sort(order.begin(), order.end(),
                         [&](int x, int y) { return -scores[x] < -scores[y]; });
        dtm.assign(T * nd, 0);
        dtig.assign(T * nd, 0);
        std::size_t col = 0;
        for (const ImageEval* e : used) {
          const std::size_t D = e->dt.size();
          const std::size_t n = std::min(max_det, D);
          for (std::size_t t = 0; t < T; ++t) {
            for (std::size_t j = 0; j < n; ++j) {
              dtm[t * nd + col + j] = e->dt_matches[t * D + j];
              dtig[t * nd + col + j] = e->dt_ignore[t * D + j];
            }
          }
          col += n;
        }
        for (std::size_t t = 0; t < T; ++t) {
          rc.resize(nd);
          pr.resize(nd);
          double tp = 0, fp = 0;
          for (std::size_t j = 0; j < nd; ++j) {
            const std::size_t c = t * nd + order[j];
            // TP / FP test dtm != 0, so a match to GT id 0 is a false positive (pycocotools).
            if (!dtig[c]) (dtm[c] != 0 ? tp : fp) += 1;
            rc[j] = tp / static_cast<double>(npig);
            pr[j] = tp / (fp + tp + kEps);
          }
          recall_[((t * K + k) * A + a) * M + m] = nd ? rc[nd - 1] : 0.0;
          for (std::size_t j = nd; j-- > 1;) {
            if (pr[j] > pr[j - 1]) pr[j - 1] = pr[j];
          }
          for (std::size_t r = 0; r < R; ++r) {
            // searchsorted(rc, r, 'left'); thresholds never reached keep precision 0.
            const auto it = std::lower_bound(rc.begin(), rc.end(), params_.recall_thresholds[r]);
            const std::size_t pi = static_cast<std::size_t>(it - rc.begin());
            const double q = pi < nd ? pr[pi] : 0.0;
            precision_[(((t * R + r) * K + k) * A + a) * M + m] = q;
          }
        }
      }
    }
  }
}

double CocoEvaluator::summarize_one(bool ap, double iou_threshold, const std::string& area,
                                    int max_dets) const {
  const std::size_t T = params_.iou_thresholds.size();
  const std::size_t R = params_.recall_thresholds.size();
  const std::size_t K = gt_.category_ids.size();
  const std::size_t A = params_.area_ranges.size();
  const std::size_t M = params_.max_dets.size();
  std::vector<std::size_t> ts;
  for (std::size_t t = 0; t < T; ++t) {
    // np.where(iouThr == p.iouThrs): exact equality, as pycocotools does.
    if (iou_threshold < 0 || params_.iou_thresholds[t] == iou_threshold) ts.push_back(t);
  }
  std::vector<std::size_t> as, ms;
  for (std::size_t a = 0; a < A; ++a) {
    if (params_.area_labels[a] == area) as.push_back(a);
  }
  for (std::size_t m = 0; m < M; ++m) {
    if (params_.max_dets[m] == max_dets) ms.push_back(m);
  }
  std::vector<double> s;
  for (std::size_t t : ts) {
    for (std::size_t r = 0; r < (ap ? R : 1); ++r) {
      for (std::size_t k = 0; k < K; ++k) {
        for (std::size_t a : as) {
          for (std::size_t m : ms) {
            const double v = ap ? precision_[(((t * R + r) * K + k) * A + a) * M + m]
                                : recall_[((t * K + k) * A + a) * M + m];
            if (v > -1) s.push_back(v);
          }
        }
      }
    }
  }
  if (s.empty()) return -1.0;
  return numpy_sum(s.data(), s.size()) / static_cast<double>(s.size());
}

std::optional<double> EvalSummary::stat(const std::string& key) const {
  for (const StatLine& line : stats) {
    if (line.key == key) return line.value < 0 ? std::nullopt : std::optional<double>(line.value);
  }
  return std::nullopt;
}

EvalSummary CocoEvaluator::summarize() const {
  if (precision_.empty())
    throw Error("internal: summarize() before accumulate()", ErrorKind::kFailure);
  struct Spec {
    const char* key;
    bool ap;
    double iou;
    const char* area;
    int max_dets;
  };
  std::vector<Spec> specs;
  if (params_.type == coco::IouType::kKeypoints) {
    specs = {{"AP", true, -1, "all", 20},      {"AP50", true, .5, "all", 20},
             {"AP75", true, .75, "all", 20},   {"APm", true, -1, "medium", 20},
             {"APl", true, -1, "large", 20},   {"AR", false, -1, "all", 20},
             {"AR50", false, .5, "all", 20},   {"AR75", false, .75, "all", 20},
             {"ARm", false, -1, "medium", 20}, {"ARl", false, -1, "large", 20}};
  } else {
    specs = {{"AP", true, -1, "all", 100},      {"AP50", true, .5, "all", 100},
             {"AP75", true, .75, "all", 100},   {"APs", true, -1, "small", 100},
             {"APm", true, -1, "medium", 100},  {"APl", true, -1, "large", 100},
             {"AR1", false, -1, "all", 1},      {"AR10", false, -1, "all", 10},
             {"AR100", false, -1, "all", 100},  {"ARs", false, -1, "small", 100},
             {"ARm", false, -1, "medium", 100}, {"ARl", false, -1, "large", 100}};
  }
  EvalSummary summary;
  summary.type = params_.type;
  char iou_all[32];
  std::snprintf(iou_all, sizeof iou_all, "%0.2f:%0.2f", params_.iou_thresholds.front(),
                params_.iou_thresholds.back());
  for (const Spec& spec : specs) {
    const double value = summarize_one(spec.ap, spec.iou, spec.area, spec.max_dets);
    char iou[32];
    if (spec.iou < 0) {
      std::snprintf(iou, sizeof iou, "%s", iou_all);
    } else {
      std::snprintf(iou, sizeof iou, "%0.2f", spec.iou);
    }
    char line[160];
    std::snprintf(line, sizeof line, " %-18s %s @[ IoU=%-9s | area=%6s | maxDets=%3d ] = %0.3f\n",
                  spec.ap ? "Average Precision" : "Average Recall", spec.ap ? "(AP)" : "(AR)", iou,
                  spec.area, spec.max_dets, value);
    summary.text += line;
    summary.stats.push_back({spec.key, value});
  }
  return summary;
}

EvalSummary run_coco_eval(const coco::CocoGroundTruth& gt, const coco::CocoResults& dt,
                          coco::IouType type, const KeypointTemplate& keypoint_template) {
  CocoEvaluator evaluator(gt, dt, type, keypoint_template);
  evaluator.evaluate();
  evaluator.accumulate();
  return evaluator.summarize();
}

}  // namespace wheelpose::eval
