// `wheelpose experiment`: an experiment file (experiment/spec.h) run as steps of child wheelpose
// commands, resumable, with a report (experiment/report.h).

#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <string>

#include "core/atomic_file.h"
#include "core/error.h"
#include "experiment/plan.h"
#include "experiment/report.h"
#include "experiment/runner.h"
#include "experiment/spec.h"

namespace wheelpose::app {

void attach_train(CLI::App& parent);

namespace {

namespace fs = std::filesystem;

struct ExperimentCommandOptions {
  std::string file, out;
  bool resume = false;
};

// The long option names `wheelpose train` accepts, read from its own CLI definition.
experiment::CommandOptions command_options() {
  CLI::App scratch;
  attach_train(scratch);
  experiment::CommandOptions options;
  for (const CLI::Option* option : scratch.get_subcommand("train")->get_options()) {
    for (const std::string& name : option->get_lnames()) options.train.insert(name);
  }
  return options;
}

experiment::Plan load_plan(const ExperimentCommandOptions& o,
                           std::vector<experiment::Variant>& variants) {
  variants = experiment::load_experiment(o.file, command_options());
  return experiment::make_plan(variants, fs::absolute(o.out).lexically_normal());
}

void run_experiment(const ExperimentCommandOptions& o) {
  std::vector<experiment::Variant> variants;
  const experiment::Plan plan = load_plan(o, variants);
  const fs::path out = fs::absolute(o.out).lexically_normal();
  std::error_code ec;
  if (fs::exists(out, ec) && !fs::is_directory(out, ec)) {
    throw Error(o.out + ": not a folder");
  }
  if (fs::exists(out / "experiment.yaml", ec) && !o.resume) {
    throw Error(o.out +
                " holds an experiment run: add --resume to continue it, or choose another --out");
  }
  fs::create_directories(out, ec);
  if (ec) throw Error(o.out + ": cannot create the folder: " + ec.message());
  const std::string config_text = read_file(o.file);
  write_file_atomic(out / "experiment.yaml", config_text);
  spdlog::info("experiment {}: {} variant(s), {} steps into {}", variants.front().spec.name,
               variants.size(), plan.steps.size(), o.out);

  const std::vector<experiment::StepRecord> records =
      experiment::run_plan(plan, fs::read_symlink("/proc/self/exe"));
  experiment::ReportInputs inputs{variants.front().spec.name,
                                  variants.front().spec.description,
                                  config_text,
                                  experiment::project_commit(),
                                  fs::path(o.file),
                                  {}};
  for (const auto& v : variants) inputs.variants.push_back(v.name);
  experiment::write_reports(experiment::collect_results(inputs, plan, records), out);
  spdlog::info("experiment {}: report in {}", inputs.name, (out / "report.md").string());
}

void print_plan(const ExperimentCommandOptions& o) {
  std::vector<experiment::Variant> variants;
  const experiment::Plan plan = load_plan(o, variants);
  for (const experiment::Step& step : plan.steps) {
    std::printf("%s\n", step.id.c_str());
    for (const auto& command : step.commands) {
      std::string line = "  wheelpose";
      for (const std::string& arg : command) line += " " + arg;
      std::printf("%s\n", line.c_str());
    }
  }
}

}  // namespace

void attach_experiment(CLI::App& parent) {
  auto* cmd = parent.add_subcommand(
      "experiment", "Run an experiment file: datasets, training, models and scores, with a report");
  cmd->require_subcommand(1);
  auto options = std::make_shared<ExperimentCommandOptions>();

  auto* run = cmd->add_subcommand(
      "run", "Run every step not yet done; write report.md, report.html and results.json in --out");
  run->add_option("file", options->file, "Experiment YAML (configs/experiments/)")->required();
  run->add_option("--out", options->out, "Run folder (steps/, the reports)")->required();
  run->add_flag("--resume", options->resume, "Continue the run in --out");
  run->callback([options] { run_experiment(*options); });

  auto* plan = cmd->add_subcommand(
      "plan", "Check the file and print the steps and their commands, without running them");
  plan->add_option("file", options->file, "Experiment YAML")->required();
  plan->add_option("--out", options->out, "Run folder the commands would write to")
      ->default_val("out/experiment");
  plan->callback([options] { print_plan(*options); });
}

}  // namespace wheelpose::app
