#include "eval/oks_iou.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace wheelpose::eval {

double numpy_sum(const double* a, std::size_t n) {
  // numpy pairwise_sum: straight loop below 8, 8 accumulators up to 128, else split in halves.
  if (n < 8) {
    double res = 0.0;
    for (std::size_t i = 0; i < n; ++i) res += a[i];
    return res;
  }
  if (n <= 128) {
    double r[8];
    for (int j = 0; j < 8; ++j) r[j] = a[j];
    std::size_t i = 8;
    for (; i < n - (n % 8); i += 8) {
      for (int j = 0; j < 8; ++j) r[j] += a[i + j];
    }
    double res = ((r[0] + r[1]) + (r[2] + r[3])) + ((r[4] + r[5]) + (r[6] + r[7]));
    for (; i < n; ++i) res += a[i];
    return res;
  }
  std::size_t n2 = n / 2;
  n2 -= n2 % 8;
  return numpy_sum(a, n2) + numpy_sum(a + n2, n - n2);
}

std::vector<double> oks_vars(const KeypointTemplate& keypoint_template) {
  std::vector<double> vars;
  for (const auto& k : keypoint_template.keypoints) vars.push_back((k.sigma * 2) * (k.sigma * 2));
  return vars;
}

double oks_exponent(double dx, double dy, double var, double area) {
  constexpr double kEps = std::numeric_limits<double>::epsilon();  // np.spacing(1)
  return (dx * dx + dy * dy) / var / (area + kEps) / 2;
}

double compute_oks(const coco::GtAnnotation& gt, std::span<const double> dt,
                   std::span<const double> vars) {
  const std::size_t k = vars.size();
  int k1 = 0;
  for (std::size_t i = 0; i < k; ++i) k1 += gt.keypoints[3 * i + 2] > 0 ? 1 : 0;
  const double x0 = gt.bbox.x - gt.bbox.w, x1 = gt.bbox.x + gt.bbox.w * 2;
  const double y0 = gt.bbox.y - gt.bbox.h, y1 = gt.bbox.y + gt.bbox.h * 2;
  // The terms of the kept keypoints, summed in numpy's order.
  thread_local std::vector<double> terms;
  terms.resize(k);
  double* e = terms.data();
  std::size_t n = 0;
  for (std::size_t i = 0; i < k; ++i) {
    const double xd = dt[3 * i], yd = dt[3 * i + 1];
    double dx, dy;
    if (k1 > 0) {
      if (!(gt.keypoints[3 * i + 2] > 0)) continue;
      dx = xd - gt.keypoints[3 * i];
      dy = yd - gt.keypoints[3 * i + 1];
    } else {
      dx = std::max(0.0, x0 - xd) + std::max(0.0, xd - x1);
      dy = std::max(0.0, y0 - yd) + std::max(0.0, yd - y1);
    }
    e[n++] = std::exp(-oks_exponent(dx, dy, vars[i], gt.area));
  }
  return numpy_sum(e, n) / static_cast<double>(n);
}

double bbox_iou(const coco::Box& dt, const coco::Box& gt, bool gt_is_crowd) {
  const double ga = gt.w * gt.h, da = dt.w * dt.h;
  const double w = std::min(dt.w + dt.x, gt.w + gt.x) - std::max(dt.x, gt.x);
  if (w <= 0) return 0.0;
  const double h = std::min(dt.h + dt.y, gt.h + gt.y) - std::max(dt.y, gt.y);
  if (h <= 0) return 0.0;
  const double i = w * h;
  const double u = gt_is_crowd ? da : da + ga - i;
  return i / u;
}

}  // namespace wheelpose::eval
