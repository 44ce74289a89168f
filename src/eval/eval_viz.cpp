#include "eval/eval_viz.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/image_read.h"
#include "eval/oks_iou.h"

namespace wheelpose::eval {
namespace {

const cv::Scalar kWhite(255, 255, 255), kRed(0, 0, 255), kGreen(0, 255, 0);

cv::Point point(const std::vector<double>& kp, int k) {
  return cv::Point(static_cast<int>(std::lround(kp[3 * k])),
                   static_cast<int>(std::lround(kp[3 * k + 1])));
}

void draw_box(cv::Mat& image, const coco::Box& b, const cv::Scalar& color) {
  cv::rectangle(image, cv::Point(static_cast<int>(b.x), static_cast<int>(b.y)),
                cv::Point(static_cast<int>(b.x + b.w), static_cast<int>(b.y + b.h)), color, 1,
                cv::LINE_AA);
}

// `labelled(k)` says whether keypoint k exists; `visible(k)` picks a filled dot over a ring.
template <typename Labelled, typename Visible>
void draw_pose(cv::Mat& image, const std::vector<double>& kp, const KeypointTemplate& t,
               const cv::Scalar& color, int thickness, Labelled labelled, Visible visible) {
  if (kp.empty()) return;
  for (const auto& [a, b] : t.skeleton) {
    if (labelled(a) && labelled(b)) {
      cv::line(image, point(kp, a), point(kp, b), color, thickness, cv::LINE_AA);
    }
  }
  for (int k = 0; k < t.size(); ++k) {
    if (!labelled(k)) continue;
    cv::circle(image, point(kp, k), 3 + thickness, color, visible(k) ? cv::FILLED : 1, cv::LINE_AA);
  }
}

void draw_detections(cv::Mat& image, const coco::CocoResults& results, std::int64_t image_id,
                     const KeypointTemplate& t, const cv::Scalar& color, double min_score) {
  for (const coco::Detection& d : results.detections) {
    if (d.image_id != image_id || d.score < min_score) continue;
    draw_box(image, d.bbox, color);
    draw_pose(
        image, d.keypoints, t, color, 1, [](int) { return true; }, [](int) { return true; });
  }
}

}  // namespace

const std::map<std::string, VizPick>& viz_pick_names() {
  static const std::map<std::string, VizPick> names = {
      {"spread", VizPick::kSpread}, {"best", VizPick::kBest}, {"worst", VizPick::kWorst}};
  return names;
}

std::vector<int> evenly_spaced(int n, int count) {
  std::vector<int> out;
  const int m = std::min(n, std::max(count, 0));
  for (int i = 0; i < m; ++i) {
    out.push_back(static_cast<int>(static_cast<long long>(i) * n / m));
  }
  return out;
}

std::vector<double> image_pose_scores(const coco::CocoGroundTruth& gt,
                                      const coco::CocoResults& results, const KeypointTemplate& t) {
  const std::vector<double> vars = oks_vars(t);
  std::vector<double> sum(gt.images.size(), 0.0);
  std::vector<int> people(gt.images.size(), 0);
  std::vector<std::vector<const coco::Detection*>> in_image(gt.images.size());
  for (const coco::Detection& d : results.detections) {
    const int position = gt.image_position(d.image_id);
    if (position >= 0 && !d.keypoints.empty()) in_image[position].push_back(&d);
  }
  for (const coco::GtAnnotation& g : gt.annotations) {
    const int position = gt.image_position(g.image_id);
    if (position < 0 || g.iscrowd || g.num_keypoints <= 0) continue;
    double best = 0;
    for (const coco::Detection* d : in_image[position]) {
      best = std::max(best, compute_oks(g, d->keypoints, vars));
    }
    sum[position] += best;
    ++people[position];
  }
  std::vector<double> scores(gt.images.size(), std::numeric_limits<double>::quiet_NaN());
  for (std::size_t i = 0; i < scores.size(); ++i) {
    if (people[i] > 0) scores[i] = sum[i] / people[i];
  }
  return scores;
}

std::vector<int> ranked_positions(const std::vector<double>& scores, int count, VizPick pick) {
  std::vector<int> positions;
  for (std::size_t i = 0; i < scores.size(); ++i) {
    if (!std::isnan(scores[i])) positions.push_back(static_cast<int>(i));
  }
  std::stable_sort(positions.begin(), positions.end(), [&](int a, int b) {
    return pick == VizPick::kWorst ? scores[a] < scores[b] : scores[a] > scores[b];
  });
  positions.resize(std::min<std::size_t>(positions.size(), std::max(count, 0)));
  return positions;
}

std::vector<std::filesystem::path> write_overlays(const coco::CocoGroundTruth& gt,
                                                  const coco::CocoResults& ours,
                                                  const coco::CocoResults* baseline,
                                                  const KeypointTemplate& t,
                                                  const VizOptions& options) {
  std::vector<std::filesystem::path> written;
  ensure_directory(options.out_dir);
  const std::vector<int> positions =
      options.pick == VizPick::kSpread
          ? evenly_spaced(static_cast<int>(gt.images.size()), options.count)
          : ranked_positions(image_pose_scores(gt, ours, t), options.count, options.pick);
  for (std::size_t rank = 0; rank < positions.size(); ++rank) {
    const int position = positions[rank];
    const coco::GtImage& info = gt.images[position];
    if (info.file_name.empty()) {
      throw Error(gt.source + ": image id " + std::to_string(info.id) +
                  " has no file_name to draw");
    }
    const std::filesystem::path source = options.images_dir / info.file_name;
    if (!std::filesystem::is_regular_file(source)) {
      throw Error(source.string() + ": image file of image id " + std::to_string(info.id) +
                  " not found (--images DIR must hold the GT images)");
    }
    cv::Mat image = read_image(source, cv::IMREAD_COLOR);
    for (const coco::GtAnnotation& g : gt.annotations) {
      if (g.image_id != info.id) continue;
      draw_box(image, g.bbox, kWhite);
      if (g.keypoints.empty()) continue;
      draw_pose(
          image, g.keypoints, t, kWhite, 2, [&](int k) { return g.keypoints[3 * k + 2] > 0; },
          [&](int k) { return g.keypoints[3 * k + 2] >= 2; });
    }
    if (baseline) draw_detections(image, *baseline, info.id, t, kRed, options.min_score);
    draw_detections(image, ours, info.id, t, kGreen, options.min_score);
    std::vector<std::uint8_t> encoded;
    if (!cv::imencode(".jpg", image, encoded)) {
      throw Error("cannot encode overlay for " + source.string(), ErrorKind::kFailure);
    }
    // Ranked picks carry their rank first so a folder listing shows them in order.
    const std::string prefix =
        options.pick == VizPick::kSpread
            ? ""
            : (options.pick == VizPick::kBest ? "best" : "worst") + std::to_string(rank + 1) + "_";
    const auto target =
        options.out_dir / (prefix + std::filesystem::path(info.file_name).stem().string() + ".jpg");
    write_file_atomic(target, std::span<const std::uint8_t>(encoded.data(), encoded.size()));
    written.push_back(target);
  }
  return written;
}

}  // namespace wheelpose::eval
