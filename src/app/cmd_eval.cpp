// `wheelpose eval`: COCO keypoint / box evaluation identical to pycocotools, plus the paper's
// per-keypoint metrics, an optional baseline comparison and overlay images.

#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "core/atomic_file.h"
#include "core/coco_data.h"
#include "core/error.h"
#include "core/keypoint_template.h"
#include "eval/bootstrap.h"
#include "eval/coco_eval.h"
#include "eval/eval_report.h"
#include "eval/eval_viz.h"
#include "eval/keypoint_metrics.h"

namespace wheelpose::app {
namespace {

struct EvalOptions {
  std::string gt;
  std::string dt;
  std::string type = "keypoints";
  std::string keypoint_template = "coco17";
  std::string baseline;
  std::string out;
  int viz = 0;
  eval::VizPick viz_pick = eval::VizPick::kSpread;
  std::string images;
  int bootstrap = 0;
  std::uint64_t bootstrap_seed = 0;
};

eval::ResultReport evaluate_file(const std::string& path, const coco::CocoGroundTruth& gt,
                                 const KeypointTemplate& t, bool keypoints, bool bbox,
                                 std::unique_ptr<coco::CocoResults>& results) {
  results = std::make_unique<coco::CocoResults>(coco::load_coco_results(path, gt, t.size()));
  // pycocotools silently drops detections of categories absent from the GT; say so.
  std::size_t foreign = 0;
  for (const auto& d : results->detections) foreign += gt.category_position(d.category_id) < 0;
  if (foreign > 0) {
    spdlog::warn("{}: {} detection(s) have a category_id not in the ground truth; ignored", path,
                 foreign);
  }
  eval::ResultReport report;
  report.results_path = path;
  if (keypoints) {
    coco::require_fields(*results, coco::IouType::kKeypoints);
    eval::CocoEvaluator evaluator(gt, *results, coco::IouType::kKeypoints, t);
    evaluator.evaluate();
    evaluator.accumulate();
    report.keypoints = evaluator.summarize();
    report.keypoint_metrics = eval::compute_keypoint_metrics(evaluator, gt, *results, t);
  }
  if (bbox) report.bbox = eval::run_coco_eval(gt, *results, coco::IouType::kBbox, t);
  return report;
}

void print_report(const eval::ResultReport& r) {
  if (r.keypoints) {
    std::printf("Keypoint evaluation of %s\n%s", r.results_path.c_str(), r.keypoints->text.c_str());
  }
  if (r.bbox) std::printf("Box evaluation of %s\n%s", r.results_path.c_str(), r.bbox->text.c_str());
  if (r.keypoint_metrics) {
    std::printf("\nPer-keypoint metrics of %s\n\n%s\n", r.results_path.c_str(),
                eval::keypoint_table_markdown(*r.keypoint_metrics).c_str());
  }
}

void run_eval(const EvalOptions& o) {
  if (o.viz > 0 && (o.images.empty() || o.out.empty())) {
    throw Error("--viz needs --images DIR (the GT images) and --out DIR");
  }
  const bool keypoints = o.type != "bbox";
  const bool bbox = o.type != "keypoints";
  const KeypointTemplate t = load_keypoint_template(o.keypoint_template);
  const coco::CocoGroundTruth gt = coco::load_coco_gt(o.gt, t.size(), keypoints);
  std::size_t orphans = 0;
  for (const auto& a : gt.annotations) orphans += gt.image_position(a.image_id) < 0;
  if (orphans > 0) {
    spdlog::warn("{}: {} annotation(s) refer to image ids not in 'images'; ignored", o.gt, orphans);
  }
  std::unique_ptr<coco::CocoResults> ours_results, base_results;
  const eval::ResultReport ours = evaluate_file(o.dt, gt, t, keypoints, bbox, ours_results);
  std::optional<eval::ResultReport> base;
  if (!o.baseline.empty()) base = evaluate_file(o.baseline, gt, t, keypoints, bbox, base_results);

  if (base) print_report(*base);
  print_report(ours);
  std::string comparison;
  if (base) {
    comparison = eval::comparison_markdown(ours, *base);
    std::printf("Comparison: %s vs baseline %s\n\n%s", o.dt.c_str(), o.baseline.c_str(),
                comparison.c_str());
  }
  nlohmann::json intervals = nlohmann::json::array();
  for (const auto type : {coco::IouType::kKeypoints, coco::IouType::kBbox}) {
    if (o.bootstrap == 0 || (type == coco::IouType::kKeypoints ? !keypoints : !bbox)) continue;
    eval::BootstrapOptions options;
    options.samples = o.bootstrap;
    options.seed = o.bootstrap_seed;
    const eval::BootstrapResult r =
        eval::bootstrap_ap(gt, *ours_results, base_results.get(), type, t, options);
    std::printf("\n%s AP, %d%% interval of %d resamples of the images (seed %llu), points:\n\n%s",
                type == coco::IouType::kKeypoints ? "Keypoint" : "Box",
                static_cast<int>(std::lround(options.level * 100)), options.samples,
                static_cast<unsigned long long>(options.seed), eval::bootstrap_markdown(r).c_str());
    intervals.push_back(eval::bootstrap_json(r));
  }
  std::fflush(stdout);
  if (o.out.empty()) return;

  const std::filesystem::path out(o.out);
  ensure_directory(out);
  auto metrics = eval::metrics_json(o.gt, t.name, ours, base ? &*base : nullptr);
  if (!intervals.empty()) metrics["bootstrap"] = intervals;
  write_file_atomic(out / "metrics.json", metrics.dump(2) + "\n");
  if (base) write_file_atomic(out / "comparison.md", comparison);
  if (o.viz > 0) {
    eval::VizOptions viz;
    viz.count = o.viz;
    viz.pick = o.viz_pick;
    viz.images_dir = o.images;
    viz.out_dir = out / "viz";
    const auto files = eval::write_overlays(gt, *ours_results, base_results.get(), t, viz);
    spdlog::info("wrote {} overlay image(s) to {}", files.size(), viz.out_dir.string());
  }
  spdlog::info("wrote {}", (out / "metrics.json").string());
}

}  // namespace

void attach_eval(CLI::App& parent) {
  auto options = std::make_shared<EvalOptions>();
  CLI::App* cmd = parent.add_subcommand(
      "eval", "COCO keypoint/box AP (identical to pycocotools) and per-keypoint metrics");
  cmd->add_option("--gt", options->gt, "COCO person-keypoints ground truth JSON")->required();
  cmd->add_option("--dt", options->dt, "COCO results JSON (list of detections)")->required();
  cmd->add_option("--type", options->type, "What to evaluate")
      ->check(CLI::IsMember({"keypoints", "bbox", "both"}))
      ->capture_default_str();
  cmd->add_option("--template", options->keypoint_template,
                  "Keypoint template: coco17 or a template JSON file (names, sigmas, skeleton)")
      ->capture_default_str();
  cmd->add_option("--baseline", options->baseline,
                  "Second results JSON to compare against (percent change, comparison.md)");
  cmd->add_option("--out", options->out, "Directory for metrics.json, comparison.md and viz/");
  cmd->add_option("--bootstrap", options->bootstrap,
                  "Resample the images this many times: 95% intervals of AP and AP50 (and, with "
                  "--baseline, of the paired difference)")
      ->check(CLI::Range(0, 1000000));
  cmd->add_option("--bootstrap-seed", options->bootstrap_seed, "Seed of the resampling")
      ->capture_default_str();
  cmd->add_option("--viz", options->viz, "Draw this many evenly spaced GT images into OUT/viz")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--viz-pick", options->viz_pick,
                  "Which images --viz draws: spread (evenly spaced), best or worst (mean OKS of "
                  "each image's people against their best detection)")
      ->transform(CLI::CheckedTransformer(eval::viz_pick_names()));
  cmd->add_option("--images", options->images, "Directory holding the GT images (for --viz)");
  cmd->callback([options] { run_eval(*options); });
}

}  // namespace wheelpose::app
