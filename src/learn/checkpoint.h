#pragma once
// checkpoint.pt: the model's parameters, the optimizer's state, the step and the run's settings
// (its resume key), written atomically; last.pt beside it. Internal to the learn layer.

#include <torch/torch.h>

#include <filesystem>
#include <string>

#include "learn/graph_module.h"

namespace wheelpose::learn {

// Writes out_dir/last.pt, then out_dir/checkpoint.pt: killed between the two, a resume starts
// from the older checkpoint and writes last.pt again (the other order could leave a stale
// last.pt behind the final checkpoint).
void save_checkpoint(GraphModule& model, torch::optim::AdamW& optimizer, int step,
                     const std::string& resume_key, const std::filesystem::path& out_dir);

// Restores model and optimizer from out_dir/checkpoint.pt and returns its step. A missing
// file, another model's checkpoint or other settings (another resume key) throw Error.
int load_checkpoint(GraphModule& model, torch::optim::AdamW& optimizer,
                    const std::string& resume_key, const std::filesystem::path& out_dir);

}  // namespace wheelpose::learn
