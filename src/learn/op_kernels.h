#pragma once
// The kernel of each TF.js op: given one graph node (its attributes and inputs), a function
// from its input tensors to its output tensors, in LibTorch. GraphModule builds one per node
// when it loads a model. Internal to the learn layer: it includes torch.

#include <torch/torch.h>

#include <functional>
#include <string>
#include <vector>

#include "learn/node_attrs.h"
#include "learn/tfjs_model.h"

namespace wheelpose::learn {

using Kernel = std::function<std::vector<torch::Tensor>(std::vector<torch::Tensor>&)>;

// What a kernel builder reads about its node, and the output count it sets.
struct KernelSite {
  const NodeAttrs& attrs;
  const torch::Tensor& constant;          // the node's value, for Const
  const std::vector<bool>& torch_layout;  // per node: a filter already in torch's layout
  const bool& channels_last;              // the module's conv memory format, read at run time
  int outputs = 1;                        // how many outputs the kernel returns
};

// The node's kernel (empty for Placeholder, whose value forward() supplies). An op without a
// kernel, or inputs and attributes it cannot take, throw Error naming the model file and node.
Kernel build_kernel(KernelSite& site);

// Which ops are convolutions: Conv2D and depthwise, each plain or with fused bias/activation.
bool is_conv(const std::string& op);
bool is_depthwise(const std::string& op);
bool is_fused(const std::string& op);

torch::ScalarType scalar_type(DType d);

// "2×3×4", or "scalar".
std::string shape_text(c10::IntArrayRef shape);

}  // namespace wheelpose::learn
