// `wheelpose demo`'s checks before it serves: each missing piece is one line naming it, exit 2.
// (The page itself is tested in chromium: tests/browser/demo_e2e.mjs.)

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "cli_runner.h"
#include "http_probe.h"

namespace {

using wheelpose::testing::fresh_temp_dir;
using wheelpose::testing::run_wheelpose;
namespace fs = std::filesystem;

TEST(DemoCli, MissingPiecesAreNamedBeforeServing) {
  if (!fs::exists(fs::path(WHEELPOSE_SOURCE_DIR) / "models" / "movenet-multipose.json")) {
    GTEST_SKIP() << "MoveNet models missing: run scripts/setup.sh";
  }
  const auto dir = fresh_temp_dir("demo_bad");
  auto r = run_wheelpose("demo --port 0 --web " + (dir / "nowhere").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("nowhere/index.html: no such file"), std::string::npos) << r.output;

  fs::create_directories(dir / "web");
  std::ofstream(dir / "web" / "index.html") << "<!doctype html>";
  r = run_wheelpose("demo --port 0 --web " + (dir / "web").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("node_modules/@tensorflow: no such folder"), std::string::npos)
      << r.output;

  r = run_wheelpose("demo --port 0 --wheelchair " + (dir / "missing.json").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("missing.json: no such model file"), std::string::npos) << r.output;

  // A .json that is not a TF.js model, and a model whose shard is missing.
  std::ofstream(dir / "plain.json") << "{\"a\": 1}";
  r = run_wheelpose("demo --port 0 --wheelchair " + (dir / "plain.json").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("plain.json: not a TF.js graph model"), std::string::npos) << r.output;
  std::ofstream(dir / "noshard.json")
      << R"({"weightsManifest": [{"paths": ["gone.bin"], "weights": []}]})";
  r = run_wheelpose("demo --port 0 --wheelchair " + (dir / "noshard.json").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("gone.bin: no such file"), std::string::npos) << r.output;
  // The ensemble's member is checked the same way.
  r = run_wheelpose("demo --port 0 --ensemble " + (dir / "plain.json").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("plain.json: not a TF.js graph model"), std::string::npos) << r.output;
}

// The demo server on loopback: slow clients do not block a visitor, malformed requests get 400.
TEST(DemoCli, SlowOrMalformedClientsDoNotStallTheServer) {
  if (!fs::exists(fs::path(WHEELPOSE_SOURCE_DIR) / "models" / "movenet-multipose.json") ||
      !fs::exists(fs::path(WHEELPOSE_SOURCE_DIR) / "web" / "demo" / "node_modules")) {
    GTEST_SKIP() << "MoveNet models or the demo's npm runtime missing: run scripts/setup.sh";
  }
  const auto dir = fresh_temp_dir("demo_slow");
  const int port = wheelpose::testing::free_port();
  wheelpose::testing::ChildServer server;
  server.start({"demo", "--port", std::to_string(port)}, dir / "demo.log");
  wheelpose::testing::expect_slow_and_malformed_clients_refused(port, "/index.html", 16);
  // The WebAssembly backend: its binaries as application/wasm (browsers compile them while they
  // download only then), and a policy that lets the page compile them and nothing more.
  const std::string wasm = wheelpose::testing::exchange(
      port,
      "GET /tfjs/tfjs-backend-wasm/dist/tfjs-backend-wasm-simd.wasm HTTP/1.1\r\nHost: x\r\n"
      "Connection: close\r\n\r\n",
      5);
  EXPECT_EQ(wheelpose::testing::status_of(wasm), 200);
  EXPECT_NE(wasm.find("Content-Type: application/wasm"), std::string::npos) << wasm.substr(0, 400);
  EXPECT_NE(wasm.find("script-src 'self' 'wasm-unsafe-eval';"), std::string::npos);
  EXPECT_EQ(wasm.find("unsafe-inline"), std::string::npos);
}

}  // namespace
