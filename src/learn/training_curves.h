#pragma once
// The training run's figure, curves.png and curves.svg in the run folder: the loss and its parts
// per step (moving average) from train_log.csv, and validation keypoint and box AP per step
// from val_log.csv when there is one. Torch-free.

#include <filesystem>

namespace wheelpose::learn {

// Throws Error when train_log.csv is missing or a row is not numbers.
void draw_training_curves(const std::filesystem::path& run_dir);

}  // namespace wheelpose::learn
