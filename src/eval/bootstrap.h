#pragma once
// How sure a COCO AP is: a percentile bootstrap over the images. Each resample draws as many
// images as the ground truth holds, with replacement, and re-accumulates the matches evaluate()
// made once, so a thousand resamples cost a thousand accumulations, not a thousand matchings.
// With a baseline the resample is paired (the same images for both), which is what says
// whether one model's gain over another is more than which photos happened to be in the set.

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/coco_data.h"
#include "core/keypoint_template.h"

namespace wheelpose::eval {

struct BootstrapOptions {
  int samples = 1000;
  std::uint64_t seed = 0;
  double level = 0.95;  // the central share of the resampled values the interval holds
};

// One COCO stat: its value on the whole set and the interval of its resampled values. A
// difference can be −1 legitimately, so what is undefined is said, not coded as −1: `estimate`
// is meaningless unless `defined`, `low` and `high` unless `resamples_used` > 0.
struct BootstrapInterval {
  std::string key;  // "AP", "AP50", …
  double estimate = -1;
  double low = -1;
  double high = -1;
  bool defined = false;    // the stat exists on the whole set (for both, in a difference)
  int resamples_used = 0;  // resamples in which it exists
};

struct BootstrapResult {
  coco::IouType type = coco::IouType::kKeypoints;
  BootstrapOptions options;
  std::vector<BootstrapInterval> ours;
  std::vector<BootstrapInterval> baseline;    // empty without a baseline
  std::vector<BootstrapInterval> difference;  // ours − baseline, paired; empty without one
};

// The stats bootstrapped: AP and AP50, the two every target here is stated in.
const std::vector<std::string>& bootstrapped_stats();

// `baseline` may be null. Resamples in which a stat is undefined (no ground truth drawn) are
// left out of that stat's interval.
BootstrapResult bootstrap_ap(const coco::CocoGroundTruth& gt, const coco::CocoResults& ours,
                             const coco::CocoResults* baseline, coco::IouType type,
                             const KeypointTemplate& keypoint_template,
                             const BootstrapOptions& options);

// Linear-interpolated percentile of sorted values (numpy's default), q in [0, 1].
double percentile_of_sorted(const std::vector<double>& sorted, double q);

// {"type", "samples", "seed", "level", "ours": {stat: {estimate, low, high, resamples_used}},
// and with a baseline "baseline" and "difference" alike}; values as fractions, like eval's
// stats, null where undefined.
nlohmann::json bootstrap_json(const BootstrapResult& result);

// A Markdown table: stat, ours [low, high], and with a baseline its interval and the paired
// difference's, in points (× 100).
std::string bootstrap_markdown(const BootstrapResult& result);

}  // namespace wheelpose::eval
