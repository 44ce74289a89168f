// `wheelpose generate`: domain-randomized frames of wheelchair users with COCO keypoint labels.

#include <spdlog/spdlog.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/config.h"
#include "core/error.h"
#include "generate/runner.h"
#include "generate/scenario.h"
#include "progress.h"

namespace wheelpose::app {
namespace {

struct GenerateCommandOptions {
  std::string config;
  std::string out;
  std::int64_t frames = 100;
  std::uint64_t seed = 0;
  std::string shard = "0/1";
  int threads = 0;
  std::string format = "jpg";
  bool resume = false;
  std::string motions;
  std::string clips_from;
  std::string assets;
  std::vector<std::string> sets;  // KEY=VALUE written over the scenario
  bool list_randomizers = false;
};

// The scenario: the --config file (or the built-in paper preset) with every --set written over it.
generate::Scenario load_scenario(const GenerateCommandOptions& o) {
  if (o.sets.empty()) {
    return o.config.empty() ? generate::Scenario::defaults()
                            : generate::Scenario::from_file(o.config);
  }
  YAML::Node root =
      o.config.empty() ? YAML::Node(YAML::NodeType::Map) : ConfigNode::parse_file(o.config);
  for (const std::string& assignment : o.sets) {
    const std::size_t equals = assignment.find('=');
    if (equals == std::string::npos || equals == 0) {
      throw Error("--set '" + assignment +
                  "': expected KEY=VALUE, e.g. labels.box=person_and_wheelchair");
    }
    YAML::Node value;
    try {
      value = YAML::Load(assignment.substr(equals + 1));
    } catch (const YAML::Exception& e) {
      throw Error("--set '" + assignment + "': the value is not YAML: " + e.msg);
    }
    try {
      set_dotted_key(root, assignment.substr(0, equals), value);
    } catch (const Error& e) {
      throw Error("--set '" + assignment + "': " + e.what());
    }
  }
  const std::string origin = (o.config.empty() ? "the paper preset" : o.config) + " with --set";
  return generate::Scenario::from_config(ConfigNode::from_yaml(root, origin));
}

std::pair<int, int> parse_shard(const std::string& text) {
  const auto slash = text.find('/');
  try {
    if (slash == std::string::npos) throw std::invalid_argument("no slash");
    std::size_t used_i = 0, used_n = 0;
    const int i = std::stoi(text.substr(0, slash), &used_i);
    const int n = std::stoi(text.substr(slash + 1), &used_n);
    if (used_i != slash || used_n != text.size() - slash - 1 || n < 1 || i < 0 || i >= n)
      throw std::invalid_argument("range");
    return {i, n};
  } catch (const std::exception&) {
    throw Error("--shard '" + text + "': expected i/N with 0 <= i < N, e.g. 0/4");
  }
}

void run(const GenerateCommandOptions& o) {
  if (o.list_randomizers) {
    std::cout << generate::randomizer_reference_markdown();
    return;
  }
  if (o.out.empty()) throw Error("--out is required");
  const generate::Scenario scenario = load_scenario(o);
  generate::RunOptions run;
  run.out = o.out;
  run.frames = o.frames;
  run.seed = o.seed;
  std::tie(run.shard_index, run.shard_count) = parse_shard(o.shard);
  run.threads = o.threads;
  run.format = o.format;
  run.resume = o.resume;
  run.motions.folder = o.motions;
  run.motions.clips_from = o.clips_from;
  if (!o.assets.empty()) run.assets = o.assets;
  Progress progress("generate", "frames");
  const generate::RunSummary s = generate::run_generate(
      scenario, run, [&progress](std::int64_t done, std::int64_t total) { progress(done, total); });
  spdlog::info(
      "generate: frames {}..{} ({} rendered, {} already done) in {:.1f} s ({:.2f} images/s); {} "
      "people labelled, {} dropped under {} visible pixels -> {}/annotations.json",
      s.first_frame, s.end_frame - 1, s.rendered, s.resumed, s.seconds,
      s.seconds > 0 ? static_cast<double>(s.rendered) / s.seconds : 0.0, s.annotations,
      s.dropped_people, scenario.min_visible_pixels, o.out);
  if (s.rendered > 0) {
    const generate::RunSummary::StageMs& ms = s.stage_ms;
    spdlog::info(
        "generate: thread ms per frame: draft {:.1f}, build {:.1f}, ray-tracing structure {:.1f}, "
        "render {:.1f}, label {:.1f}, write {:.1f}",
        ms.draft, ms.build, ms.bvh, ms.render, ms.label, ms.write);
  }
}

}  // namespace

void attach_generate(CLI::App& parent) {
  auto o = std::make_shared<GenerateCommandOptions>();
  CLI::App* cmd = parent.add_subcommand(
      "generate", "Render domain-randomized scenes of wheelchair users with COCO keypoint labels");
  cmd->add_option("--config", o->config,
                  "Scenario YAML (default: the paper preset, "
                  "configs/wheelpose-paper.yaml)");
  cmd->add_option("--set", o->sets,
                  "KEY=VALUE written over the scenario (dotted keys, a YAML value), e.g. "
                  "labels.box=person_and_wheelchair; repeatable, recorded in scenario.json");
  cmd->add_option("--out", o->out, "Output folder (images/, labels/, annotations.json)");
  cmd->add_option("--frames", o->frames, "Frames in the whole dataset (all shards)")
      ->check(CLI::Range(std::int64_t{1}, std::int64_t{1} << 40));
  cmd->add_option("--seed", o->seed, "Scenario seed");
  cmd->add_option("--shard", o->shard, "Render shard i of N: frames [i*n/N, (i+1)*n/N)");
  cmd->add_option("--threads", o->threads, "Worker threads (0 = all cores)")
      ->check(CLI::Range(0, 1024));
  cmd->add_option("--format", o->format, "Image format")->check(CLI::IsMember({"jpg", "png"}));
  cmd->add_flag("--resume", o->resume,
                "Keep frames already written by the same command; render the rest");
  cmd->add_option("--motions", o->motions,
                  "Folder of seated clip JSON from `wheelpose motion` (default: built-in library)");
  cmd->add_option("--clips-from", o->clips_from,
                  "ranking.json from `wheelpose review filter`: use only the kept clips");
  cmd->add_option("--assets", o->assets, "Body asset root (holds makehuman/)");
  cmd->add_flag("--list-randomizers", o->list_randomizers,
                "Print the randomizer reference (Markdown) and exit");
  cmd->callback([o] { run(*o); });
}

}  // namespace wheelpose::app
