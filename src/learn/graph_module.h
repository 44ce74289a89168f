#pragma once
// Executes a TF.js graph model (learn/tfjs_model.h) with LibTorch ops, differentiably.
// Internal to the learn layer: it includes torch, so headers used by the app must not include it.
//
// Every tensor keeps TensorFlow's logical layout (NHWC images), so shape ops (Shape,
// StridedSlice, Reshape, ...) see exactly what TF sees. Convolutions, depthwise convolutions
// and pooling run on an NCHW view of the same tensor: with channels-last memory (the default,
// faster on CPU) permute(0, 3, 1, 2) of an NHWC-contiguous tensor is free and the conv output
// permutes back for free; with channels_last off the conv input is made NCHW-contiguous.
//
// Float constants consumed as convolution filters or biases are trainable parameters
// (registered under their node names, '.' replaced by '_'), stored in torch's layout: Conv2D
// filters [out, in, kh, kw] (TF: [kh, kw, in, out]), depthwise filters [in*mult, 1, kh, kw]
// (TF: [kh, kw, in, mult]). Every other constant is a fixed tensor.
//
// Convolutions call oneDNN (at::mkldnn_convolution) directly: ATen's own heuristic sends small
// batch-1 convolutions to im2col + BLAS, which with Debian's reference BLAS is the slowest path.
// forward() caches an execution plan per capture list, so one module must not run forward() on
// two threads at once.

#include <torch/torch.h>

#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "learn/op_kernels.h"
#include "learn/tfjs_model.h"

namespace wheelpose::learn {

using TensorMap = std::unordered_map<std::string, torch::Tensor>;

class GraphModule : public torch::nn::Module {
 public:
  explicit GraphModule(TfjsModel model);
  explicit GraphModule(const std::filesystem::path& topology_json);

  // Runs the graph on `input` (1×H×W×3 NHWC, int32 0..255 or float; float keeps the input
  // differentiable). Returns the signature outputs under their tensor names (e.g.
  // "Identity:0") plus the captured tensors under the names they were requested by. Works
  // under torch::NoGradGuard / torch::InferenceMode for inference and with grad for training.
  TensorMap forward(const torch::Tensor& input);
  TensorMap forward(const torch::Tensor& input, const std::vector<std::string>& capture);

  // Only the named internal tensors, for training: the signature outputs and the decoding
  // behind them are not computed, so the batch (dimension 0) may hold any number of images.
  TensorMap forward_only(const torch::Tensor& input, const std::vector<std::string>& names);

  // Internal tensors ("node" or "node:k") that forward(input) also returns. Unknown names
  // throw Error naming the model file.
  void set_capture(std::vector<std::string> names);
  const std::vector<std::string>& capture() const { return capture_; }

  // Channels-last memory for the conv path (default on).
  void set_channels_last(bool on) { channels_last_ = on; }
  bool channels_last() const { return channels_last_; }

  const TfjsModel& graph() const { return model_; }
  // The signature output names, e.g. {"Identity:0"}.
  std::vector<std::string> output_names() const;
  // The graph node each trainable parameter comes from, in registration order.
  const std::vector<std::string>& parameter_nodes() const { return parameter_nodes_; }
  // Trainable parameter of graph node `node_name` (torch layout); throws Error if none.
  torch::Tensor parameter(const std::string& node_name) const;
  // The current value of Const node `node_name` in TensorFlow's layout and shape (a trained
  // filter back to [kh, kw, in, out] or [kh, kw, in, mult]), detached; throws Error if the
  // node is not a Const.
  torch::Tensor tf_value(const std::string& node_name) const;

  // Fine-tuned weights as a .pt (torch::pickle_save of a dict: format, version, model name,
  // parameters keyed by node name, torch layout), loadable by Python's torch.load. load()
  // refuses a file from another model (names or shapes differ) with one line naming it.
  using torch::nn::Module::load;
  using torch::nn::Module::save;
  void save(const std::filesystem::path& path) const;
  void load(const std::filesystem::path& path);

 private:
  struct Plan {
    std::vector<int> steps;                 // node indices to run, in order
    std::vector<std::vector<int>> release;  // per step: nodes whose outputs die after it
    std::vector<std::string> names;         // returned names
    std::vector<TensorRef> refs;            // ... and the tensors they name
  };
  void compile();
  // Constants as tensors, float filters and biases as parameters; per node, whether it is a
  // filter stored in torch's layout.
  std::vector<bool> make_constants();
  // Every input and signature output names an output its node makes.
  void check_references() const;
  const Plan& plan_for(const std::vector<std::string>& capture, bool with_outputs);
  TensorMap run(const torch::Tensor& input, const Plan& plan, bool any_batch);

  TfjsModel model_;
  bool channels_last_ = true;
  std::vector<Kernel> kernels_;           // per node
  std::vector<int> output_counts_;        // per node: how many outputs it produces
  std::vector<torch::Tensor> constants_;  // per node: Const values (params share storage)
  std::vector<bool> torch_layout_;        // per node: a filter stored in torch's layout
  std::unordered_map<std::string, std::string> param_by_node_;  // node -> registered name
  std::vector<std::string> parameter_nodes_;
  std::vector<std::string> capture_;
  std::unordered_map<std::string, Plan> plans_;  // keyed by the joined capture list
};

}  // namespace wheelpose::learn
