#pragma once
// Training throughput without data loading, for bench_learn: optimizer steps of MoveNet
// MultiPose on one fixed batch, exactly as `train` runs them (learn/train_step.h), with the conv
// layout switchable to compare channels-last against NCHW. Torch-free.

#include <filesystem>
#include <memory>
#include <vector>

#include "learn/train_data.h"

namespace wheelpose::learn {

class TrainStepProbe {
 public:
  // `samples`: the batch (augment's outputs, all input_size²). `threads`: 0 = every core.
  TrainStepProbe(const std::filesystem::path& model_json, const std::vector<TrainSample>& samples,
                 int input_size, bool channels_last, int threads);
  ~TrainStepProbe();
  TrainStepProbe(const TrainStepProbe&) = delete;
  TrainStepProbe& operator=(const TrainStepProbe&) = delete;

  double step();  // one AdamW step (lr 1e-5); returns the loss before it

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace wheelpose::learn
