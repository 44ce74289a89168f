#pragma once
// `wheelpose demo`: a local page where a person drops a photo (or picks a bundled example) and
// sees the pretrained and the wheelchair model side by side, and the real-photo ensemble (the
// pretrained model with a second one, each on the photo and its mirror image, as `predict
// --model A --model B --flip` fuses them), all run in the browser by TF.js on their TF.js graph
// models. The server only serves files: the page (web/demo), the TF.js runtime from
// web/demo/node_modules (nothing from the internet), the three models and the examples, each
// under its own URL prefix and nothing else.

#include <filesystem>
#include <string>

namespace wheelpose::demo {

struct DemoOptions {
  std::string bind = "127.0.0.1";
  int port = 8090;                            // 0 picks a free port (printed)
  std::filesystem::path web_dir;              // the page; empty: the checkout's web/demo
  std::filesystem::path pretrained_topology;  // .json of the left model
  std::filesystem::path wheelchair_topology;  // .json of the middle model
  std::filesystem::path ensemble_topology;    // .json of the ensemble's second member
  std::filesystem::path examples_dir;         // images the page offers; empty: WEB/examples
};

// Checks every folder and file first (one line naming what is missing, exit 2), then serves
// until SIGINT/SIGTERM; prints "listening on URL".
void serve_demo(DemoOptions options);

}  // namespace wheelpose::demo
