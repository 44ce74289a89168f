#pragma once
// One entry per `wheelpose` subcommand. Each command lives in its own cmd_<name>.cpp and adds
// itself (with its options and callback) to the parent CLI11 app; the table is in commands.cpp.

#include <CLI/CLI.hpp>
#include <vector>

namespace wheelpose::app {

struct Command {
  const char* name;
  void (*attach)(CLI::App& parent);
};

const std::vector<Command>& command_table();

}  // namespace wheelpose::app
