// `wheelpose motion convert|library|preview`: the motion stage on the command line.

#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <filesystem>
#include <memory>

#include "core/atomic_file.h"
#include "core/config.h"
#include "core/error.h"
#include "motion/batch.h"
#include "motion/clip_json.h"
#include "motion/importers.h"
#include "motion/library.h"
#include "motion/preview.h"

namespace wheelpose::app {

namespace {

using namespace wheelpose::motion;

struct PipelineFlags {
  std::string config;
  std::uint64_t seed = 0;
  bool seed_given = false;
  std::string exports = "json,glb,bvh";
};

void add_pipeline_flags(CLI::App& command, PipelineFlags& flags) {
  command.add_option("--config", flags.config,
                     "YAML file with a `motion:` section (see configs/motion.yaml)");
  command.add_option("--seed", flags.seed, "Seed for the leg noise (and library variants)");
  command.add_option("--exports", flags.exports,
                     "Comma-separated outputs per clip: json, glb, bvh, fbx (binary), "
                     "fbx-ascii (<name>.ascii.fbx)")
      ->capture_default_str();
}

MotionOptions pipeline_options(const PipelineFlags& flags, CLI::App& command) {
  MotionOptions options;
  if (!flags.config.empty()) {
    ConfigNode root = ConfigNode::load_file(flags.config);
    if (auto section = root.optional_child("motion")) options = MotionOptions::from_config(*section);
    root.finish();
  }
  if (command.count("--seed")) options.seed = flags.seed;
  return options;
}

int report(const BatchResult& result, const std::filesystem::path& out, std::size_t total) {
  for (const std::string& failure : result.failures) spdlog::error("{}", failure);
  spdlog::info("{} of {} clips written to {}", result.written.size(), total, out.string());
  if (!result.failures.empty()) {
    throw Error(std::to_string(result.failures.size()) + " of " + std::to_string(total) +
                " clips were rejected (see above)");
  }
  return 0;
}

void attach_convert(CLI::App& motion) {
  auto* command = motion.add_subcommand(
      "convert", "Convert motion files (HumanML3D .npy, BVH, CSV/JSON keypoints) to seated clips");
  struct Flags {
    std::vector<std::string> inputs;
    std::string out;
    ImportOptions import;
    PipelineFlags pipeline;
  };
  auto flags = std::make_shared<Flags>();
  command->add_option("inputs", flags->inputs, "Motion files")->required();
  command->add_option("--out", flags->out, "Output directory")->required();
  command->add_option("--format", flags->import.format, "Input format: npy, bvh, csv, json "
                                                        "(default: from the extension)");
  command->add_option("--fps", flags->import.fps, "Source frame rate (default: the format's)")
      ->check(CLI::PositiveNumber);
  command->add_option("--mapping", flags->import.mapping,
                      "Joint mapping: npy: smpl22; bvh: cmu, cmu_mb; csv/json: wheelpose23, blazepose33");
  command->add_option("--unit-scale", flags->import.unit_scale,
                      "Metres per source unit (default: the mapping's)")
      ->check(CLI::PositiveNumber);
  add_pipeline_flags(*command, flags->pipeline);
  command->callback([flags, command] {
    const MotionOptions options = pipeline_options(flags->pipeline, *command);
    const auto exporters = parse_exporter_list(flags->pipeline.exports);
    const BatchResult result = convert_batch(
        flags->inputs.size(),
        [&](std::size_t i) { return import_motion(flags->inputs[i], flags->import); }, options,
        exporters, flags->out);
    report(result, flags->out, flags->inputs.size());
  });
}

void attach_library(CLI::App& motion) {
  auto* command = motion.add_subcommand(
      "library", "Write the built-in seated motion library through the pipeline");
  struct Flags {
    std::string out;
    bool list = false;
    PipelineFlags pipeline;
  };
  auto flags = std::make_shared<Flags>();
  command->add_option("--out", flags->out, "Output directory");
  command->add_flag("--list", flags->list, "Only list the built-in motions");
  add_pipeline_flags(*command, flags->pipeline);
  command->callback([flags, command] {
    if (flags->list) {
      for (const auto& info : library_motions()) {
        std::printf("%-28s %-20s %s\n", info.id.c_str(), info.activity_class.c_str(),
                    info.description.c_str());
      }
      return;
    }
    if (flags->out.empty()) throw Error("--out is required (or use --list)");
    const MotionOptions options = pipeline_options(flags->pipeline, *command);
    const auto exporters = parse_exporter_list(flags->pipeline.exports);
    const auto motions = library_motions();
    const BatchResult result = convert_batch(
        motions.size(), [&](std::size_t i) { return library_clip(motions[i].id, options.seed); },
        options, exporters, flags->out);
    nlohmann::ordered_json index = nlohmann::ordered_json::array();
    for (const auto& info : motions) {
      index.push_back({{"id", info.id},
                       {"class", info.activity_class},
                       {"description", info.description}});
    }
    write_file_atomic(std::filesystem::path(flags->out) / "library.json",
                      nlohmann::ordered_json{{"seed", options.seed}, {"clips", index}}.dump(2) +
                          "\n");
    report(result, flags->out, motions.size());
  });
}

void attach_preview(CLI::App& motion) {
  auto* command = motion.add_subcommand(
      "preview", "Draw a seated clip as a looping four-view skeleton GIF");
  struct Flags {
    std::string clip;
    std::string out;
    int size = 256;
    double fps = 0;
  };
  auto flags = std::make_shared<Flags>();
  command->add_option("clip", flags->clip, "Seated clip JSON (from convert or library)")
      ->required();
  command->add_option("--out", flags->out, "GIF file to write")->required();
  command->add_option("--size", flags->size, "Pixel size of each of the four views")
      ->check(CLI::Range(64, 1024))
      ->capture_default_str();
  command->add_option("--fps", flags->fps, "Playback rate (default: the clip's)")
      ->check(CLI::PositiveNumber);
  command->callback([flags] {
    const SeatedClip clip = read_seated_clip_json(flags->clip);
    PreviewOptions options;
    options.view_size = flags->size;
    options.fps = flags->fps;
    write_preview_gif(clip.positions, clip.motion.fps, flags->out, options);
    spdlog::info("wrote {} ({} frames)", flags->out, clip.positions.size());
  });
}

}  // namespace

void attach_motion(CLI::App& parent) {
  auto* motion = parent.add_subcommand("motion", "Motion stage: seated wheelchair-user clips");
  motion->require_subcommand(1);
  attach_convert(*motion);
  attach_library(*motion);
  attach_preview(*motion);
}

}  // namespace wheelpose::app
