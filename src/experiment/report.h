#pragma once
// What an experiment run reports, from the eval folders its steps wrote: results.json (every
// number, the experiment file, the project's commit, wall times), report.md and report.html
// (the tables per scored set and the training curves).

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "experiment/plan.h"
#include "experiment/runner.h"

namespace wheelpose::experiment {

struct ReportInputs {
  std::string name, description, config_text, commit;
  std::filesystem::path config_file;
  std::vector<std::string> variants;
};

// The checkout's commit (git describe --dirty), "unknown" outside a git checkout.
std::string project_commit();

// results.json's content. Scores whose metrics.json is missing are left out.
nlohmann::json collect_results(const ReportInputs& inputs, const Plan& plan,
                               const std::vector<StepRecord>& steps);

std::string report_markdown(const nlohmann::json& results);
// The training curves are linked relative to the run folder, where report.html goes.
std::string report_html(const nlohmann::json& results);

// Writes the three files into `out_dir` atomically.
void write_reports(const nlohmann::json& results, const std::filesystem::path& out_dir);

}  // namespace wheelpose::experiment
