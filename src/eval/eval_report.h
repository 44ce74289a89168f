#pragma once
// metrics.json and the Markdown tables of `wheelpose eval`: one result file's numbers, and with a
// baseline both files' numbers plus percent change (ours vs baseline), laid out like the paper's
// Table 6.

#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "eval/coco_eval.h"
#include "eval/keypoint_metrics.h"

namespace wheelpose::eval {

// Everything measured for one results file.
struct ResultReport {
  std::string results_path;
  std::optional<EvalSummary> keypoints;
  std::optional<EvalSummary> bbox;
  std::optional<KeypointMetrics> keypoint_metrics;
};

// (ours - baseline) / |baseline| * 100; nullopt if either is missing, negative (-1 = undefined
// COCO stat) where it makes no sense, or the baseline is 0.
std::optional<double> percent_change(std::optional<double> ours, std::optional<double> baseline);

nlohmann::json report_to_json(const ResultReport& report);

// {"gt", "template", "results": {...}, optional "baseline": {...}, "change_percent": {...}}.
nlohmann::json metrics_json(const std::string& gt_path, const std::string& template_name,
                            const ResultReport& ours, const ResultReport* baseline);

// Per-group table of one result file (PDJ@5, PJPE, OKS50, OKS75, counts).
std::string keypoint_table_markdown(const KeypointMetrics& metrics);

// COCO stats side by side and the per-group table of ours with percent change vs baseline.
std::string comparison_markdown(const ResultReport& ours, const ResultReport& baseline);

}  // namespace wheelpose::eval
