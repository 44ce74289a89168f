#include "demo/demo_server.h"

#include <httplib.h>

#include <algorithm>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/image_files.h"
#include "http/http_host.h"

namespace wheelpose::demo {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// The page only reads files and models: requests carry no body worth more than this.
constexpr std::size_t kMaxDemoRequestBytes = 64 * 1024;

void require_file(const fs::path& file, const std::string& what) {
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) throw Error(file.string() + ": no such file (" + what + ")");
}

void require_dir(const fs::path& dir, const std::string& what) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw Error(dir.string() + ": no such folder (" + what + ")");
}

// Serves `topology` as PREFIX/model.json and its folder under PREFIX, where TF.js looks for the
// shards its manifest names (relative to model.json).
void mount_model(httplib::Server& server, const std::string& prefix, const fs::path& topology) {
  require_file(topology, "a TF.js model.json");
  const json doc = json::parse(read_file(topology), nullptr, /*allow_exceptions=*/false);
  if (!doc.is_object() || !doc.contains("weightsManifest") || !doc["weightsManifest"].is_array()) {
    throw Error(topology.string() + ": not a TF.js graph model (no weightsManifest)");
  }
  for (const json& group : doc["weightsManifest"]) {
    for (const json& path : group.value("paths", json::array())) {
      if (!path.is_string()) throw Error(topology.string() + ": a shard path is not a string");
      require_file(topology.parent_path() / path.get<std::string>(),
                   "a weight shard of " + topology.filename().string());
    }
  }
  const std::string text = doc.dump();
  server.Get(prefix + "/model.json", [text](const httplib::Request&, httplib::Response& res) {
    res.set_content(text, "application/json");
  });
  if (!server.set_mount_point(prefix, topology.parent_path().string())) {
    throw Error(topology.parent_path().string() + ": cannot serve this folder",
                ErrorKind::kFailure);
  }
}

// A model's name on the page: its file's stem, or its folder's for an export's model.json.
std::string display_name(const fs::path& topology) {
  const std::string stem = topology.stem().string();
  return stem == "model" ? topology.parent_path().filename().string() : stem;
}

}  // namespace

void serve_demo(DemoOptions options) {
  const sigset_t signals = http::block_stop_signals();
  if (options.web_dir.empty()) options.web_dir = fs::path(WHEELPOSE_SOURCE_DIR) / "web" / "demo";
  if (options.examples_dir.empty()) options.examples_dir = options.web_dir / "examples";
  require_file(options.web_dir / "index.html", "the demo page; give --web DIR");
  const fs::path tfjs = options.web_dir / "node_modules" / "@tensorflow";
  require_dir(tfjs, "the TF.js runtime: npm ci in " + options.web_dir.string() +
                        " (scripts/setup.sh does it)");
  require_dir(options.examples_dir, "the example images");

  httplib::Server server;
  http::set_connection_limits(server, kMaxDemoRequestBytes);
  http::set_security_headers(server, {.blob_images = true, .wasm = true});
  // Browsers compile WebAssembly while it downloads only when it is served as such.
  server.set_file_extension_and_mimetype_mapping("wasm", "application/wasm");
  for (const auto& [prefix, dir] : std::vector<std::pair<std::string, fs::path>>{
           {"/tfjs", tfjs}, {"/examples", options.examples_dir}}) {
    if (!server.set_mount_point(prefix, dir.string())) {
      throw Error(dir.string() + ": cannot serve this folder", ErrorKind::kFailure);
    }
  }
  mount_model(server, "/models/pretrained", options.pretrained_topology);
  mount_model(server, "/models/wheelchair", options.wheelchair_topology);
  mount_model(server, "/models/ensemble", options.ensemble_topology);
  std::vector<std::string> examples;
  for (const fs::path& file : image_files_in(options.examples_dir)) {
    examples.push_back(file.filename().string());
  }
  std::sort(examples.begin(), examples.end());
  const std::string config =
      json{{"examples", examples},
           {"models",
            {{{"key", "pretrained"}, {"name", display_name(options.pretrained_topology)}},
             {{"key", "wheelchair"}, {"name", display_name(options.wheelchair_topology)}},
             {{"key", "ensemble"}, {"name", display_name(options.ensemble_topology)}}}}}
          .dump();
  server.Get("/api/config", [config](const httplib::Request&, httplib::Response& res) {
    res.set_content(config, "application/json");
  });
  // Last: the page itself (mount points are tried in order of registration).
  if (!server.set_mount_point("/", options.web_dir.string())) {
    throw Error(options.web_dir.string() + ": cannot serve this folder", ErrorKind::kFailure);
  }
  const std::string url = http::bind_server(server, options.bind, options.port);
  std::printf("demo: pretrained %s, wheelchair %s, ensemble member %s\nlistening on %s\n",
              options.pretrained_topology.string().c_str(),
              options.wheelchair_topology.string().c_str(),
              options.ensemble_topology.string().c_str(), url.c_str());
  std::fflush(stdout);
  http::listen_until_signal(server, signals);
}

}  // namespace wheelpose::demo
