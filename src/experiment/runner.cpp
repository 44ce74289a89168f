#include "experiment/runner.h"

#include <fcntl.h>
#include <spdlog/spdlog.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/atomic_file.h"
#include "core/error.h"

namespace wheelpose::experiment {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

fs::path done_file(const Step& step) { return step.dir / "done.json"; }

std::string last_line(const fs::path& log) {
  std::ifstream in(log);
  std::string line, last;
  while (std::getline(in, line)) {
    if (line.find_first_not_of(" \t\r") != std::string::npos) last = line;
  }
  return last;
}

// Runs `program args...` with stdout and stderr appended to `log`; returns the exit status. The
// child dies with this process (a killed run leaves no step running behind it: the resumed run
// would race it for the step's folder).
int run_child(const fs::path& program, const std::vector<std::string>& args, const fs::path& log) {
  std::vector<std::string> argv_text = {program.string()};
  argv_text.insert(argv_text.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : argv_text) argv.push_back(a.data());
  argv.push_back(nullptr);
  const int log_fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if (log_fd < 0)
    throw Error(log.string() + ": cannot write: " + std::strerror(errno), ErrorKind::kFailure);
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid == 0) {
    // Only async-signal-safe calls until exec.
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (::getppid() != parent) ::_exit(127);
    ::dup2(log_fd, STDOUT_FILENO);
    ::dup2(log_fd, STDERR_FILENO);
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  ::close(log_fd);
  if (pid < 0)
    throw Error(std::string("cannot start a step: ") + std::strerror(errno), ErrorKind::kFailure);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) throw Error("waitpid failed", ErrorKind::kFailure);
  }
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  return 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}

// Whether an unfinished step's folder holds work its command can continue.
bool can_continue(const Step& step) {
  if (!step.resumable) return false;
  std::error_code ec;
  if (step.kind == "train") return fs::exists(step.dir / "checkpoint.pt", ec);
  return fs::exists(step.dir / "scenario.json", ec);
}

StepRecord record_of(const Step& step, double seconds) {
  return {step.id, step.kind, step.label, seconds};
}

}  // namespace

std::vector<StepRecord> run_plan(const Plan& plan, const fs::path& program) {
  std::vector<StepRecord> records;
  const std::size_t total = plan.steps.size();
  for (std::size_t i = 0; i < total; ++i) {
    const Step& step = plan.steps[i];
    std::error_code ec;
    if (fs::exists(done_file(step), ec)) {
      const json done = json::parse(read_file(done_file(step)), nullptr, false);
      if (!done.is_object() || !done.contains("seconds")) {
        throw Error(done_file(step).string() + ": damaged (delete the step's folder to redo it)");
      }
      spdlog::info("[{}/{}] {}: done before", i + 1, total, step.label);
      records.push_back(record_of(step, done["seconds"].get<double>()));
      continue;
    }
    const bool resume = can_continue(step);
    if (!resume) fs::remove_all(step.dir);
    fs::create_directories(step.dir);
    spdlog::info("[{}/{}] {}{}", i + 1, total, step.label, resume ? " (resuming)" : "");
    const fs::path log = step.dir / "log.txt";
    const auto start = std::chrono::steady_clock::now();
    for (std::vector<std::string> args : step.commands) {
      if (resume) args.push_back("--resume");  // only generate and train steps resume
      const int status = run_child(program, args, log);
      if (status != 0) {
        throw Error("step '" + step.label + "' failed (exit " + std::to_string(status) +
                        "): " + last_line(log) + " (log: " + log.string() + ")",
                    ErrorKind::kFailure);
      }
    }
    if (!step.link_images.empty()) {
      fs::create_directory_symlink(step.link_images, step.dir / "images");
    }
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    json done = {{"seconds", seconds}, {"commands", step.commands}};
    write_file_atomic(done_file(step), done.dump(1) + "\n");
    records.push_back(record_of(step, seconds));
  }
  return records;
}

}  // namespace wheelpose::experiment
