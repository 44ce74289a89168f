#include "app/command.h"

namespace wheelpose::app {


const std::vector<Command>& command_table() {
  static const std::vector<Command> table = {
  };
  return table;
}

}  // namespace wheelpose::app
