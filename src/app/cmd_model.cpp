// `wheelpose model`: a fine-tuned model as a product. `export` writes a TF.js graph model that
// any MoveNet runtime loads; `blend` interpolates two models' weights (WiSE-FT).

#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "app/cli_checks.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/text_escape.h"
#include "learn/model_export.h"
#include "learn/model_files.h"

namespace wheelpose::app {
namespace {

namespace fs = std::filesystem;

struct ModelCommandOptions {
  std::string source;
  std::string start = "movenet-multipose";
  std::string finetuned;
  std::string models;
  std::string out;
  double alpha = 0.5;
  std::vector<std::string> part_alphas;  // PART=ALPHA
  bool float32 = false;
};

std::optional<fs::path> models_dir(const ModelCommandOptions& o) {
  if (o.models.empty()) return std::nullopt;
  return fs::path(o.models);
}

void run_export(const ModelCommandOptions& o) {
  const learn::ModelChoice source = learn::choose_model(o.source, models_dir(o));
  const learn::ExportSummary s = learn::export_tfjs_model(source, o.out, {.float32 = o.float32});
  spdlog::info("model export: {} weights ({} trained) of {} as {} into {} ({} bytes)", s.weights,
               s.parameters, s.base_model, o.float32 ? "float32" : "float16",
               (fs::path(o.out) / learn::kExportTopology).string(), s.bin_bytes);
}

void run_blend(const ModelCommandOptions& o) {
  check_output_file(o.out);
  const learn::ModelChoice start = learn::choose_model(o.start, models_dir(o));
  const learn::ModelChoice tuned = learn::choose_model(o.finetuned, models_dir(o));
  learn::BlendAlphas alphas{.alpha = o.alpha, .part_alphas = {}};
  for (const std::string& spec : o.part_alphas) {
    const std::size_t eq = spec.rfind('=');
    const std::optional<double> alpha = eq != std::string::npos && eq > 0
                                            ? parse_number(std::string_view(spec).substr(eq + 1))
                                            : std::nullopt;
    if (!alpha || *alpha < 0 || *alpha > 1) {
      throw Error("--alpha-for: '" + escape_bytes(spec) +
                  "' is not PART=ALPHA with ALPHA a number in [0, 1]");
    }
    alphas.part_alphas.emplace_back(spec.substr(0, eq), *alpha);
  }
  learn::blend_weights(start, tuned, alphas, o.out);
  spdlog::info("model blend: {} + {} x ({} - start) into {}", o.start, o.alpha, o.finetuned, o.out);
}

void add_models_option(CLI::App* cmd, ModelCommandOptions& o) {
  cmd->add_option("--models", o.models,
                  "Folder of the models (default: $WHEELPOSE_MODELS, ./models, the checkout's)");
}

}  // namespace

void attach_model(CLI::App& parent) {
  auto options = std::make_shared<ModelCommandOptions>();
  CLI::App* cmd = parent.add_subcommand(
      "model", "Export a fine-tuned model to TF.js, or blend two models' weights");
  cmd->require_subcommand(1);

  CLI::App* exp = cmd->add_subcommand(
      "export",
      "Write a model (a .pt from wheelpose train, a TF.js .json or a name) as a TF.js graph "
      "model: OUT/model.json + OUT/group1-shard1of1.bin, the source's topology and signature");
  exp->add_option("model", options->source, "The model to export, e.g. RUN/best.pt")->required();
  exp->add_option("--out", options->out, "Folder to write")->required();
  exp->add_flag("--float32", options->float32,
                "Store the weights as float32 (default float16, like the published MoveNet)");
  add_models_option(exp, *options);
  exp->callback([options] { run_export(*options); });

  CLI::App* blend = cmd->add_subcommand(
      "blend",
      "Interpolate weights: start + alpha x (finetuned - start), written as a .pt (WiSE-FT: "
      "keeps what the start model knows while adding what fine-tuning taught)");
  blend->add_option("--start", options->start, "The start model (a name, .json or .pt)")
      ->capture_default_str();
  blend->add_option("--finetuned", options->finetuned, "The fine-tuned .pt")->required();
  blend->add_option("--alpha", options->alpha, "0 = the start model, 1 = the fine-tuned one")
      ->check(number_from(0, 1))
      ->capture_default_str();
  blend->add_option("--alpha-for", options->part_alphas,
                    "PART=ALPHA: this alpha for the parameters whose name contains PART, e.g. "
                    "feature_extractor (the backbone) or kpt_ / box_ / center_ (heads); "
                    "repeatable, the first match wins");
  blend->add_option("--out", options->out, ".pt to write")->required();
  add_models_option(blend, *options);
  blend->callback([options] { run_blend(*options); });
}

}  // namespace wheelpose::app
