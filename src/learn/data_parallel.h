#pragma once
// Data-parallel training over processes and machines with LibTorch's c10d Gloo backend (Debian's
// libtorch-dev ships it; its headers need libgloo-dev). Each process computes the gradients of
// its share of the batch; GradientAverager sums them over the processes and divides by their
// count, so every process takes the same optimizer step. Internal to `learn` (includes torch).

#include <torch/torch.h>

#include <memory>
#include <string>
#include <vector>

#include "learn/trainer.h"

namespace c10d {
class ProcessGroupGloo;
}

namespace wheelpose::learn {

class GradientAverager {
 public:
  // Joins the group: `rendezvous` is "tcp://HOST:PORT" (rank 0 listens there, the others
  // connect) or "file:///PATH" (a file on a filesystem every process shares; it must not be
  // left over from another run). Throws Error for a malformed address or a failed join.
  GradientAverager(const std::string& rendezvous, int rank, int world_size);
  ~GradientAverager();
  GradientAverager(const GradientAverager&) = delete;
  GradientAverager& operator=(const GradientAverager&) = delete;

  // Averages the parameters' gradients (absent ones count as zero) and the loss parts in
  // `parts` over every process, in one all-reduce.
  void average(const std::vector<torch::Tensor>& parameters, StepReport& parts);
  // Waits until every process reaches it.
  void barrier();

 private:
  std::unique_ptr<c10d::ProcessGroupGloo> group_;
  int world_size_;
};

}  // namespace wheelpose::learn
