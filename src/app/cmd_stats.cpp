// `wheelpose stats`: the paper's dataset statistics for a COCO keypoint file, optionally beside a
// reference dataset (e.g. COCO): figures (PNG + SVG), stats.json and index.html.

#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "dataset/coco_file.h"
#include "dataset/stats.h"
#include "dataset/stats_report.h"

namespace wheelpose::app {
namespace {

struct StatsOptions {
  std::string dataset;
  std::string reference;
  std::string out;
  std::string label;
  std::string reference_label;
};

dataset::DatasetStats load_stats(const std::string& path, const std::string& label) {
  const dataset::json root = dataset::load_json(path);
  dataset::require_usable(root, path);
  return dataset::compute_stats(
      root, path, label.empty() ? std::filesystem::path(path).stem().string() : label);
}

void run_stats(const StatsOptions& o) {
  std::vector<dataset::DatasetStats> data;
  data.push_back(load_stats(o.dataset, o.label));
  if (!o.reference.empty()) data.push_back(load_stats(o.reference, o.reference_label));
  for (const auto& d : data) {
    if (!d.camera_note.empty()) spdlog::info("{}: {}", d.source, d.camera_note);
  }
  const auto figures = dataset::write_stats_report(data, o.out);
  spdlog::info("{}: stats.json, index.html and {} figures", o.out, figures.size());
}

}  // namespace

void attach_stats(CLI::App& parent) {
  auto o = std::make_shared<StatsOptions>();
  auto* cmd = parent.add_subcommand(
      "stats", "Dataset statistics and figures (boxes, visibility, keypoint maps, camera)");
  cmd->add_option("dataset", o->dataset, "COCO keypoint file")->required();
  cmd->add_option("--reference", o->reference, "A second COCO file shown beside it (e.g. COCO)");
  cmd->add_option("--label", o->label, "Name of the dataset in figures (default: file stem)");
  cmd->add_option("--reference-label", o->reference_label,
                  "Name of the reference in figures (default: file stem)");
  cmd->add_option("--out", o->out, "Output directory")->required();
  cmd->callback([o] { run_stats(*o); });
}

}  // namespace wheelpose::app
