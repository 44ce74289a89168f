// `wheelpose demo`: the pretrained and the wheelchair model side by side on a dropped photo, and
// the real-photo ensemble, run in the browser by TF.js (demo/demo_server.h).

#include <CLI/CLI.hpp>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "demo/demo_server.h"
#include "learn/model_files.h"

namespace wheelpose::app {
namespace {

namespace fs = std::filesystem;

struct DemoCommandOptions {
  demo::DemoOptions server;
  std::string pretrained = "movenet-multipose";
  std::string wheelchair = "movenet-wheelchair";
  std::string ensemble = "movenet-wheelchair-full";
  std::string models;
  std::string web;
  std::string examples;
};

void run_demo(DemoCommandOptions o) {
  std::optional<fs::path> models_dir;
  if (!o.models.empty()) models_dir = fs::path(o.models);
  o.server.pretrained_topology = learn::resolve_model(o.pretrained, models_dir);
  o.server.wheelchair_topology = learn::resolve_model(o.wheelchair, models_dir);
  o.server.ensemble_topology = learn::resolve_model(o.ensemble, models_dir);
  o.server.web_dir = o.web;            // empty: the checkout's web/demo
  o.server.examples_dir = o.examples;  // empty: WEB/examples
  demo::serve_demo(o.server);
}

}  // namespace

void attach_demo(CLI::App& parent) {
  auto options = std::make_shared<DemoCommandOptions>();
  CLI::App* cmd = parent.add_subcommand(
      "demo",
      "Serve a local page: drop a photo, see the pretrained and the wheelchair model side by "
      "side and the real-photo ensemble (run in the browser by TF.js)");
  cmd->add_option("--port", options->server.port, "Port (0 picks a free one)")
      ->check(CLI::Range(0, 65535))
      ->capture_default_str();
  cmd->add_option("--bind", options->server.bind, "Address to listen on")->capture_default_str();
  cmd->add_option("--pretrained", options->pretrained, "Left model (a name or a TF.js .json)")
      ->capture_default_str();
  cmd->add_option("--wheelchair", options->wheelchair,
                  "Middle model (a name or a TF.js .json, e.g. from wheelpose model export)")
      ->capture_default_str();
  cmd->add_option("--ensemble", options->ensemble,
                  "The model fused with the pretrained one in the right panel, both also on the "
                  "mirror image (predict --model PRETRAINED --model THIS --flip)")
      ->capture_default_str();
  cmd->add_option("--models", options->models,
                  "Folder of the models (default: $WHEELPOSE_MODELS, ./models, the checkout's)");
  cmd->add_option("--web", options->web, "The page's folder (default: the checkout's web/demo)");
  cmd->add_option("--examples", options->examples,
                  "Folder of example images the page offers (default: WEB/examples)");
  cmd->callback([options] { run_demo(*options); });
}

}  // namespace wheelpose::app
