// The `wheelpose` command. Exit codes: 0 success, 1 failure, 2 bad input or usage.

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>

#include "app/command.h"
#include "core/allocator.h"
#include "core/error.h"
#include "core/text_escape.h"

int main(int argc, char** argv) {
  wheelpose::retain_freed_memory();
  CLI::App app{"WheelPose: synthetic training data for pose estimation of wheelchair users"};
  app.require_subcommand(1);
  app.set_help_all_flag("--help-all", "Print help for every command");
  bool verbose = false;
  bool quiet = false;
  app.add_flag("-v,--verbose", verbose, "Log debugging detail");
  app.add_flag("-q,--quiet", quiet, "Log only warnings and errors");
  app.parse_complete_callback([&] {
    spdlog::set_level(verbose ? spdlog::level::debug
                      : quiet ? spdlog::level::warn
                              : spdlog::level::info);
  });
  // Logs go to stderr, so `--out /dev/stdout` (or a pipe) carries only the command's output.
  spdlog::set_default_logger(spdlog::stderr_color_mt("wheelpose"));
  spdlog::set_pattern("%^%l%$: %v");
  for (const auto& command : wheelpose::app::command_table()) command.attach(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    std::fprintf(stderr, "Run with --help for usage.\n");
    return 2;
  } catch (const wheelpose::Error& e) {
    // Escaped: a control byte or byte-order mark from a user's file stays visible, on one line.
    std::fprintf(stderr, "error: %s\n", wheelpose::escape_bytes(e.what()).c_str());
    return e.exit_code();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", wheelpose::escape_bytes(e.what()).c_str());
    return 1;
  }
  return 0;
}
