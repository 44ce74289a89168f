#include "app/command.h"

namespace wheelpose::app {

void attach_motion(CLI::App& parent);
void attach_eval(CLI::App& parent);
void attach_body(CLI::App& parent);
void attach_render(CLI::App& parent);
void attach_generate(CLI::App& parent);
void attach_review(CLI::App& parent);
void attach_coco(CLI::App& parent);
void attach_stats(CLI::App& parent);
void attach_predict(CLI::App& parent);
void attach_realism(CLI::App& parent);
void attach_train(CLI::App& parent);
void attach_model(CLI::App& parent);
void attach_demo(CLI::App& parent);
void attach_experiment(CLI::App& parent);

const std::vector<Command>& command_table() {
  static const std::vector<Command> table = {
      {"motion", attach_motion},   {"eval", attach_eval},         {"body", attach_body},
      {"render", attach_render},   {"generate", attach_generate}, {"review", attach_review},
      {"coco", attach_coco},       {"stats", attach_stats},       {"predict", attach_predict},
      {"realism", attach_realism}, {"train", attach_train},       {"model", attach_model},
      {"demo", attach_demo},       {"experiment", attach_experiment},
  };
  return table;
}

}  // namespace wheelpose::app
