// The bash scripts kept for a release or two as thin wrappers over `wheelpose experiment run`:
// boost.sh --quick is the quick experiment file (and resumes), and every flag or environment
// variable of the old bash experiment is refused with one line naming what replaced it.

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_runner.h"

namespace {

namespace fs = std::filesystem;
using wheelpose::testing::fresh_temp_dir;
using wheelpose::testing::read_text;

struct ScriptRun {
  int exit_code = -1;
  std::string output;
};

// `env` (VAR=value …, may be empty) bash scripts/SCRIPT ARGS, stdout and stderr together.
ScriptRun run_script(const fs::path& dir, const std::string& env, const std::string& script,
                     const std::string& args) {
  const fs::path log = dir / "log.txt";
  const std::string command = (env.empty() ? "" : "env " + env + " ") + "bash " +
                              (fs::path(WHEELPOSE_SOURCE_DIR) / "scripts" / script).string() + " " +
                              args + " > " + log.string() + " 2>&1";
  const int status = std::system(command.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, read_text(log)};
}

TEST(ExperimentScripts, OldFlagsAndVariablesAreRefusedWithWhatReplacedThem) {
  const fs::path dir = fresh_temp_dir("experiment_scripts_refuse");
  const fs::path out = dir / "out";
  const struct {
    std::string env, script, args, expected;
  } cases[] = {
      {"", "boost.sh", "--recipe transfer",
       "--recipe is gone: use configs/experiments/transfer.yaml"},
      {"", "boost.sh", "--ablate", "--ablate is gone: use configs/experiments/sizes.yaml"},
      {"", "boost.sh", "--mix-standing", "use configs/experiments/standing-mix.yaml"},
      {"", "boost.sh", "--real x.json", "--real is gone: use a coco: dataset and a scores: entry"},
      {"", "boost.sh", "--ranking r.json", "--ranking is gone: use clips_from: RANKING.json"},
      {"", "boost.sh", "--bogus", "boost: unknown option --bogus"},
      {"WISE=0.5", "boost.sh", "--quick", "boost: the environment variable WISE is no longer read"},
      {"STEPS=10", "ablate.sh", "", "ablate: the environment variable STEPS is no longer read"},
      {"", "standing-mix.sh", "--real x.json", "standing-mix: --real is gone"},
      {"SHIP_DIR=/tmp", "ship-model.sh", "", "ship-model: the environment variable SHIP_DIR"},
  };
  for (const auto& c : cases) {
    const ScriptRun r = run_script(dir, c.env, c.script, c.args + " " + out.string());
    EXPECT_EQ(r.exit_code, 2) << c.script << " " << c.args << ": " << r.output;
    EXPECT_NE(r.output.find(c.expected), std::string::npos) << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    EXPECT_FALSE(fs::exists(out)) << c.script << " " << c.args;
  }
  fs::remove_all(dir);
}

TEST(ExperimentScripts, BoostQuickRunsTheQuickExperimentAndResumes) {
  if (!fs::exists(fs::path(WHEELPOSE_SOURCE_DIR) / "models" / "movenet-multipose.json")) {
    GTEST_SKIP() << "MoveNet models missing: run scripts/setup.sh";
  }
  const fs::path dir = fresh_temp_dir("experiment_scripts_boost");
  const fs::path out = dir / "run";
  const ScriptRun first = run_script(dir, "", "boost.sh", "--quick " + out.string());
  ASSERT_EQ(first.exit_code, 0) << first.output;
  const std::string results = read_text(out / "results.json");
  const auto parsed = nlohmann::json::parse(results);
  EXPECT_EQ(parsed["experiment"], "quick");
  EXPECT_FALSE(parsed["results"].empty());
  // Run again on the finished folder: it continues (nothing left to do) instead of refusing.
  const ScriptRun again = run_script(dir, "", "boost.sh", "--quick " + out.string());
  ASSERT_EQ(again.exit_code, 0) << again.output;
  EXPECT_EQ(read_text(out / "results.json"), results);
  fs::remove_all(dir);
}

}  // namespace
