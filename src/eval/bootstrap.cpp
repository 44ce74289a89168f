#include "eval/bootstrap.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>

#include "core/error.h"
#include "core/random.h"
#include "eval/coco_eval.h"

namespace wheelpose::eval {
namespace {

// A stat, or pycocotools' −1 when it is undefined (nothing to score in this resample).
double stat_of(const EvalSummary& summary, const std::string& key) {
  return summary.stat(key).value_or(-1.0);
}

// Resampled values of each stat, then their interval around the whole set's value.
struct Samples {
  std::vector<std::vector<double>> values;  // per stat
  std::vector<double> estimates;
  std::vector<bool> defined;

  BootstrapInterval interval(std::size_t stat, const BootstrapOptions& o) {
    std::vector<double>& v = values[stat];
    std::sort(v.begin(), v.end());
    BootstrapInterval out{bootstrapped_stats()[stat], estimates[stat], -1, -1, defined[stat],
                          static_cast<int>(v.size())};
    if (!v.empty()) {
      const double tail = (1 - o.level) / 2;
      out.low = percentile_of_sorted(v, tail);
      out.high = percentile_of_sorted(v, 1 - tail);
    }
    return out;
  }
};

}  // namespace

const std::vector<std::string>& bootstrapped_stats() {
  static const std::vector<std::string> keys = {"AP", "AP50"};
  return keys;
}

double percentile_of_sorted(const std::vector<double>& sorted, double q) {
  if (sorted.empty()) return -1;
  const double at = q * static_cast<double>(sorted.size() - 1);
  const std::size_t below = static_cast<std::size_t>(std::floor(at));
  const std::size_t above = std::min(below + 1, sorted.size() - 1);
  return sorted[below] + (sorted[above] - sorted[below]) * (at - static_cast<double>(below));
}

BootstrapResult bootstrap_ap(const coco::CocoGroundTruth& gt, const coco::CocoResults& ours,
                             const coco::CocoResults* baseline, coco::IouType type,
                             const KeypointTemplate& keypoint_template,
                             const BootstrapOptions& options) {
  if (options.samples < 1) throw Error("--bootstrap: needs at least 1 resample");
  if (!(options.level > 0 && options.level < 1)) {
    throw Error("internal: bootstrap level must be in (0, 1)", ErrorKind::kFailure);
  }
  const std::vector<std::string>& keys = bootstrapped_stats();
  CocoEvaluator ours_eval(gt, ours, type, keypoint_template);
  ours_eval.evaluate();
  ours_eval.accumulate();
  std::optional<CocoEvaluator> base_eval;
  if (baseline) {
    base_eval.emplace(gt, *baseline, type, keypoint_template);
    base_eval->evaluate();
    base_eval->accumulate();
  }
  Samples ours_samples, base_samples, difference_samples;
  for (Samples* s : {&ours_samples, &base_samples, &difference_samples}) {
    s->values.assign(keys.size(), {});
    s->estimates.assign(keys.size(), -1);
    s->defined.assign(keys.size(), false);
  }
  const EvalSummary ours_full = ours_eval.summarize();
  for (std::size_t k = 0; k < keys.size(); ++k) {
    ours_samples.estimates[k] = stat_of(ours_full, keys[k]);
    ours_samples.defined[k] = ours_samples.estimates[k] >= 0;
    if (base_eval) {
      base_samples.estimates[k] = stat_of(base_eval->summarize(), keys[k]);
      base_samples.defined[k] = base_samples.estimates[k] >= 0;
      difference_samples.estimates[k] = ours_samples.estimates[k] - base_samples.estimates[k];
      difference_samples.defined[k] = ours_samples.defined[k] && base_samples.defined[k];
    }
  }

  const std::size_t images = gt.images.size();
  std::vector<int> weights(images);
  for (int sample = 0; sample < options.samples && images > 0; ++sample) {
    // One stream per resample: resample i is the same whatever the count before it.
    RandomStream draw(options.seed, {"bootstrap", sample});
    std::fill(weights.begin(), weights.end(), 0);
    for (std::size_t i = 0; i < images; ++i) {
      ++weights[draw.uniform_int(0, static_cast<std::int64_t>(images) - 1)];
    }
    ours_eval.accumulate(weights);
    const EvalSummary o = ours_eval.summarize();
    std::optional<EvalSummary> b;
    if (base_eval) {
      base_eval->accumulate(weights);
      b = base_eval->summarize();
    }
    for (std::size_t k = 0; k < keys.size(); ++k) {
      const double ov = stat_of(o, keys[k]);
      if (ov >= 0) ours_samples.values[k].push_back(ov);
      if (!b) continue;
      const double bv = stat_of(*b, keys[k]);
      if (bv >= 0) base_samples.values[k].push_back(bv);
      if (ov >= 0 && bv >= 0) difference_samples.values[k].push_back(ov - bv);
    }
  }

  BootstrapResult result;
  result.type = type;
  result.options = options;
  for (std::size_t k = 0; k < keys.size(); ++k) {
    result.ours.push_back(ours_samples.interval(k, options));
    if (!base_eval) continue;
    result.baseline.push_back(base_samples.interval(k, options));
    result.difference.push_back(difference_samples.interval(k, options));
  }
  return result;
}

nlohmann::json bootstrap_json(const BootstrapResult& r) {
  const auto intervals = [](const std::vector<BootstrapInterval>& list) {
    nlohmann::json out = nlohmann::json::object();
    for (const BootstrapInterval& i : list) {
      const bool spread = i.resamples_used > 0;
      out[i.key] = {{"estimate", i.defined ? nlohmann::json(i.estimate) : nlohmann::json()},
                    {"low", spread ? nlohmann::json(i.low) : nlohmann::json()},
                    {"high", spread ? nlohmann::json(i.high) : nlohmann::json()},
                    {"resamples_used", i.resamples_used}};
    }
    return out;
  };
  nlohmann::json out = {{"type", r.type == coco::IouType::kKeypoints ? "keypoints" : "bbox"},
                        {"samples", r.options.samples},
                        {"seed", r.options.seed},
                        {"level", r.options.level},
                        {"ours", intervals(r.ours)}};
  if (!r.baseline.empty()) {
    out["baseline"] = intervals(r.baseline);
    out["difference"] = intervals(r.difference);
  }
  return out;
}

std::string bootstrap_markdown(const BootstrapResult& r) {
  const auto cell = [](const BootstrapInterval& i) {
    if (!i.defined || i.resamples_used == 0) return std::string("–");
    char text[96];
    std::snprintf(text, sizeof text, "%.1f [%.1f, %.1f]", i.estimate * 100, i.low * 100,
                  i.high * 100);
    return std::string(text);
  };
  const bool paired = !r.baseline.empty();
  std::string out =
      paired ? "| stat | ours | baseline | ours − baseline (paired) |\n|---|---|---|---|\n"
             : "| stat | ours |\n|---|---|\n";
  for (std::size_t k = 0; k < r.ours.size(); ++k) {
    out += "| " + r.ours[k].key + " | " + cell(r.ours[k]);
    if (paired) out += " | " + cell(r.baseline[k]) + " | " + cell(r.difference[k]);
    out += " |\n";
  }
  return out;
}

}  // namespace wheelpose::eval
