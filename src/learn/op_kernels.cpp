#include "learn/op_kernels.h"

#include <cstdint>
#include <map>
#include <optional>
#include <utility>

#include "learn/graph_ops.h"

namespace wheelpose::learn {
using torch::Tensor;

namespace {

using V = std::vector<Tensor>;
using Builder = std::function<Kernel(KernelSite&)>;
using UnaryFn = Tensor (*)(const Tensor&);
using BinaryFn = Tensor (*)(const Tensor&, const Tensor&);

// The fused bias and activation of _FusedConv2D / FusedDepthwiseConv2dNative into `spec`.
void read_fused_ops(const NodeAttrs& a, ops::ConvSpec& spec) {
  const std::size_t args = static_cast<std::size_t>(a.i("num_args"));
  a.inputs(2 + args);
  const std::vector<std::string> fused = a.strings("fused_ops");
  std::size_t next = 0;
  if (next < fused.size() && fused[next] == "BiasAdd") {
    spec.bias = true;
    ++next;
  }
  if (next < fused.size()) {
    const std::string& act = fused[next++];
    static const std::map<std::string, ops::Activation> activations = {
        {"Relu", ops::Activation::kRelu},  {"Relu6", ops::Activation::kRelu6},
        {"Elu", ops::Activation::kElu},    {"Sigmoid", ops::Activation::kSigmoid},
        {"Tanh", ops::Activation::kTanh},  {"LeakyRelu", ops::Activation::kLeakyRelu},
        {"Prelu", ops::Activation::kPrelu}};
    auto found = activations.find(act);
    if (found == activations.end()) {
      next = fused.size() + 1;  // unsupported
    } else {
      spec.activation = found->second;
      spec.alpha = a.f("leakyrelu_alpha", 0.2);
    }
  }
  const std::size_t needed_args =
      (spec.bias ? 1 : 0) + (spec.activation == ops::Activation::kPrelu ? 1 : 0);
  if (next != fused.size() || needed_args != args) {
    std::string list;
    for (const std::string& f : fused) list += (list.empty() ? "" : ",") + f;
    a.fail("fused_ops [" + list + "] with num_args " + std::to_string(args) +
           " is not supported (BiasAdd then Relu, Relu6, Elu, LeakyRelu, Sigmoid, Tanh or Prelu)");
  }
}

// Conv2D, DepthwiseConv2dNative and their fused forms.
Kernel convolution(KernelSite& site, bool depthwise) {
  const NodeAttrs& a = site.attrs;
  ops::ConvSpec spec;
  spec.depthwise = depthwise;
  a.nhwc();
  const auto strides = a.hw("strides", 1);
  const auto dilations = a.hw("dilations", 1);
  spec.stride = {strides[0], strides[1]};
  spec.dilation = {dilations[0], dilations[1]};
  spec.padding = a.padding();
  if (is_fused(a.node().op)) {
    read_fused_ops(a, spec);
  } else {
    a.inputs(2);
  }
  spec.filter_in_torch_layout = site.torch_layout[a.node().inputs[1].node];
  return [spec, &channels_last = site.channels_last](V& in) {
    const Tensor bias = spec.bias ? in[2] : Tensor();
    const Tensor prelu =
        spec.activation == ops::Activation::kPrelu ? in[spec.bias ? 3 : 2] : Tensor();
    return V{ops::conv2d_nhwc(in[0], in[1], bias, prelu, spec, channels_last)};
  };
}

Kernel max_pool(KernelSite& site) {
  const NodeAttrs& a = site.attrs;
  a.inputs(1);
  a.nhwc();
  const auto ksize = a.hw("ksize", 1);
  const auto strides = a.hw("strides", 1);
  const ops::Padding padding = a.padding();
  return [ksize, strides, padding, &channels_last = site.channels_last](V& in) {
    return V{ops::max_pool_nhwc(in[0], {ksize[0], ksize[1]}, {strides[0], strides[1]}, padding,
                                channels_last)};
  };
}

Kernel resize_bilinear(KernelSite& site) {
  const NodeAttrs& a = site.attrs;
  a.inputs(2);
  const bool align = a.b("align_corners", false);
  const bool half = a.b("half_pixel_centers", false);
  if (align && half) a.fail("align_corners and half_pixel_centers cannot both be true");
  return [align, half](V& in) {
    const std::vector<std::int64_t> size = ops::int_values(in[1]);
    if (size.size() != 2 || size[0] <= 0 || size[1] <= 0) {
      throw ops::OpError("size must be 2 positive values");
    }
    return V{ops::resize_bilinear(in[0], size[0], size[1], align, half)};
  };
}

Kernel cast(KernelSite& site) {
  site.attrs.inputs(1);
  const std::optional<DType> dst = site.attrs.type("DstT");
  if (!dst) site.attrs.fail("attr 'DstT' is missing");
  return [dst = scalar_type(*dst)](V& in) { return V{ops::cast(in[0], dst)}; };
}

Kernel reduction(KernelSite& site, ops::Reduction r) {
  site.attrs.inputs(2);
  const bool keep = site.attrs.b("keep_dims", false);
  return [r, keep](V& in) { return V{ops::reduce(in[0], ops::int_values(in[1]), r, keep)}; };
}

Kernel strided_slice(KernelSite& site) {
  const NodeAttrs& a = site.attrs;
  a.inputs(4);
  ops::SliceMasks m;
  m.begin = a.i("begin_mask", 0);
  m.end = a.i("end_mask", 0);
  m.ellipsis = a.i("ellipsis_mask", 0);
  m.new_axis = a.i("new_axis_mask", 0);
  m.shrink_axis = a.i("shrink_axis_mask", 0);
  return [m](V& in) {
    return V{ops::strided_slice(in[0], ops::int_values(in[1]), ops::int_values(in[2]),
                                ops::int_values(in[3]), m)};
  };
}

Kernel pack(KernelSite& site) {
  site.attrs.inputs(1, SIZE_MAX);
  const std::int64_t axis = site.attrs.i("axis", 0);
  return [axis](V& in) {
    const std::int64_t rank = in[0].dim() + 1;
    if (axis < -rank || axis >= rank) throw ops::OpError("axis out of range");
    return V{torch::stack(in, axis < 0 ? axis + rank : axis)};
  };
}

Kernel unpack(KernelSite& site) {
  site.attrs.inputs(1);
  const std::int64_t num = site.attrs.i("num");
  const std::int64_t axis = site.attrs.i("axis", 0);
  site.outputs = static_cast<int>(num);
  return [axis, num](V& in) {
    const std::int64_t rank = in[0].dim();
    if (axis < -rank || axis >= rank) throw ops::OpError("axis out of range");
    const std::vector<Tensor> parts = in[0].unbind(axis < 0 ? axis + rank : axis);
    if (static_cast<std::int64_t>(parts.size()) != num) {
      throw ops::OpError("the axis has " + std::to_string(parts.size()) + " entries, num is " +
                         std::to_string(num));
    }
    return parts;
  };
}

Kernel split(KernelSite& site) {
  site.attrs.inputs(2);
  const std::int64_t num = site.attrs.i("num_split");
  site.outputs = static_cast<int>(num);
  return [num](V& in) {
    std::int64_t axis = ops::int_value(in[0]);
    const Tensor& x = in[1];
    if (axis < 0) axis += x.dim();
    if (axis < 0 || axis >= x.dim() || num <= 0 || x.size(axis) % num != 0) {
      throw ops::OpError("cannot split dimension " + std::to_string(axis) + " of " +
                         shape_text(x.sizes()) + " into " + std::to_string(num));
    }
    return x.split(x.size(axis) / num, axis);
  };
}

// A kernel with a fixed input count and no attributes.
Builder plain(std::size_t inputs, Kernel kernel) {
  return [inputs, kernel = std::move(kernel)](KernelSite& site) {
    site.attrs.inputs(inputs);
    return kernel;
  };
}

// Shape and Size: a property of the input as out_type (int32 unless set).
Builder measure(bool size) {
  return [size](KernelSite& site) -> Kernel {
    site.attrs.inputs(1);
    const torch::ScalarType out = scalar_type(site.attrs.type("out_type").value_or(DType::kInt32));
    if (size) {
      return [out](V& in) { return V{torch::scalar_tensor(in[0].numel(), torch::kLong).to(out)}; };
    }
    return [out](V& in) { return V{torch::tensor(in[0].sizes().vec(), torch::kLong).to(out)}; };
  };
}

const std::map<std::string, UnaryFn>& unary_ops() {
  static const std::map<std::string, UnaryFn> ops = {
      {"StopGradient", [](const Tensor& x) { return x.detach(); }},
      {"Abs", [](const Tensor& x) { return x.abs(); }},
      {"Neg", [](const Tensor& x) { return -x; }},
      {"Exp", [](const Tensor& x) { return x.exp(); }},
      {"Log", [](const Tensor& x) { return x.log(); }},
      {"Sqrt", [](const Tensor& x) { return x.sqrt(); }},
      {"Rsqrt", [](const Tensor& x) { return x.rsqrt(); }},
      {"Square", [](const Tensor& x) { return x * x; }},
      {"Reciprocal", [](const Tensor& x) { return x.reciprocal(); }},
      {"Floor", [](const Tensor& x) { return x.floor(); }},
      {"Sigmoid", [](const Tensor& x) { return x.sigmoid(); }},
      {"Tanh", [](const Tensor& x) { return x.tanh(); }},
      {"Relu", [](const Tensor& x) { return x.relu(); }},
      {"Relu6", [](const Tensor& x) { return x.clamp(0, 6); }},
      {"LogicalNot", [](const Tensor& x) { return x.logical_not(); }},
  };
  return ops;
}

const std::map<std::string, BinaryFn>& binary_ops() {
  static const std::map<std::string, BinaryFn> ops = {
      {"Add", [](const Tensor& x, const Tensor& y) { return x + y; }},
      {"AddV2", [](const Tensor& x, const Tensor& y) { return x + y; }},
      {"Sub", [](const Tensor& x, const Tensor& y) { return x - y; }},
      {"Mul", [](const Tensor& x, const Tensor& y) { return x * y; }},
      {"RealDiv", [](const Tensor& x, const Tensor& y) { return x / y; }},
      {"FloorDiv", ops::floor_div},
      {"Maximum", [](const Tensor& x, const Tensor& y) { return torch::maximum(x, y); }},
      {"Minimum", [](const Tensor& x, const Tensor& y) { return torch::minimum(x, y); }},
      {"SquaredDifference",
       [](const Tensor& x, const Tensor& y) {
         const Tensor d = x - y;
         return d * d;
       }},
      {"Equal", [](const Tensor& x, const Tensor& y) { return x.eq(y); }},
      {"NotEqual", [](const Tensor& x, const Tensor& y) { return x.ne(y); }},
      {"Less", [](const Tensor& x, const Tensor& y) { return x.lt(y); }},
      {"LessEqual", [](const Tensor& x, const Tensor& y) { return x.le(y); }},
      {"Greater", [](const Tensor& x, const Tensor& y) { return x.gt(y); }},
      {"GreaterEqual", [](const Tensor& x, const Tensor& y) { return x.ge(y); }},
      {"LogicalAnd", [](const Tensor& x, const Tensor& y) { return x.logical_and(y); }},
      {"LogicalOr", [](const Tensor& x, const Tensor& y) { return x.logical_or(y); }},
  };
  return ops;
}

// Ops whose kernel needs more than a fixed input count and a tensor function.
std::map<std::string, Builder> structural_ops() {
  std::map<std::string, Builder> b;
  b["Const"] = [](KernelSite& site) -> Kernel {
    site.attrs.inputs(0);
    return [t = site.constant](V&) { return V{t}; };
  };
  b["Placeholder"] = [](KernelSite& site) -> Kernel {
    site.attrs.inputs(0);
    return nullptr;  // forward() supplies the input
  };
  b["Identity"] = b["Snapshot"] = plain(1, [](V& in) { return V{in[0]}; });
  b["NoOp"] = [](KernelSite& site) -> Kernel {
    site.outputs = 0;
    return [](V&) { return V{}; };
  };
  for (const char* op : {"Conv2D", "_FusedConv2D"}) {
    b[op] = [](KernelSite& site) { return convolution(site, false); };
  }
  for (const char* op : {"DepthwiseConv2dNative", "FusedDepthwiseConv2dNative"}) {
    b[op] = [](KernelSite& site) { return convolution(site, true); };
  }
  b["BiasAdd"] = [](KernelSite& site) -> Kernel {
    site.attrs.inputs(2);
    site.attrs.nhwc();
    return [](V& in) { return V{in[0] + in[1]}; };
  };
  b["MaxPool"] = max_pool;
  b["ResizeBilinear"] = resize_bilinear;
  b["Cast"] = cast;
  b["AddN"] = [](KernelSite& site) -> Kernel {
    site.attrs.inputs(1, SIZE_MAX);
    return [](V& in) {
      Tensor sum = in[0];
      for (std::size_t j = 1; j < in.size(); ++j) sum = sum + in[j];
      return V{sum};
    };
  };
  b["Select"] = plain(3, [](V& in) { return V{ops::select_v1(in[0], in[1], in[2])}; });
  b["SelectV2"] = plain(3, [](V& in) { return V{torch::where(in[0], in[1], in[2])}; });
  for (const auto& [op, r] :
       std::map<std::string, ops::Reduction>{{"Sum", ops::Reduction::kSum},
                                             {"Max", ops::Reduction::kMax},
                                             {"Min", ops::Reduction::kMin},
                                             {"Mean", ops::Reduction::kMean}}) {
    b[op] = [r](KernelSite& site) { return reduction(site, r); };
  }
  b["ArgMax"] = [](KernelSite& site) -> Kernel {
    site.attrs.inputs(2);
    const torch::ScalarType out =
        scalar_type(site.attrs.type("output_type").value_or(DType::kInt64));
    return [out](V& in) { return V{ops::arg_max(in[0], ops::int_value(in[1])).to(out)}; };
  };
  b["TopKV2"] = [](KernelSite& site) -> Kernel {
    site.attrs.inputs(2);
    site.outputs = 2;
    return [](V& in) {
      auto [values, indices] = ops::top_k(in[0], ops::int_value(in[1]));
      return V{values, indices};
    };
  };
  b["GatherNd"] = plain(2, [](V& in) { return V{ops::gather_nd(in[0], in[1])}; });
  b["Shape"] = measure(false);
  b["Size"] = measure(true);
  b["Reshape"] = plain(2, [](V& in) { return V{in[0].reshape(ops::int_values(in[1]))}; });
  b["Squeeze"] = [](KernelSite& site) -> Kernel {
    site.attrs.inputs(1);
    const std::vector<std::int64_t> dims =
        site.attrs.ints("squeeze_dims", std::vector<std::int64_t>{});
    return [dims](V& in) { return V{ops::squeeze_dims(in[0], dims)}; };
  };
  b["ExpandDims"] = plain(2, [](V& in) {
    std::int64_t dim = ops::int_value(in[1]);
    const std::int64_t rank = in[0].dim();
    if (dim < -rank - 1 || dim > rank) throw ops::OpError("dim out of range");
    if (dim < 0) dim += rank + 1;
    return V{in[0].unsqueeze(dim)};
  });
  b["StridedSlice"] = strided_slice;
  b["Pack"] = pack;
  b["Unpack"] = unpack;
  b["ConcatV2"] = [](KernelSite& site) -> Kernel {
    site.attrs.inputs(2, SIZE_MAX);
    return [](V& in) {
      const std::int64_t axis = ops::int_value(in.back());
      in.pop_back();
      return V{torch::cat(in, axis)};
    };
  };
  b["Split"] = split;
  b["Tile"] = plain(2, [](V& in) {
    const std::vector<std::int64_t> reps = ops::int_values(in[1]);
    if (static_cast<std::int64_t>(reps.size()) != in[0].dim()) {
      throw ops::OpError("multiples has " + std::to_string(reps.size()) + " values for a rank-" +
                         std::to_string(in[0].dim()) + " tensor");
    }
    return V{in[0].repeat(reps)};
  });
  b["Fill"] = plain(2, [](V& in) {
    if (in[1].numel() != 1) throw ops::OpError("value must be a scalar");
    return V{in[1].reshape({}).expand(ops::int_values(in[0])).contiguous()};
  });
  b["Range"] = plain(3, [](V& in) { return V{ops::range(in[0], in[1], in[2])}; });
  b["Transpose"] = plain(2, [](V& in) { return V{in[0].permute(ops::int_values(in[1]))}; });
  b["Pad"] = plain(2, [](V& in) {
    const std::vector<std::int64_t> p = ops::int_values(in[1]);
    if (static_cast<std::int64_t>(p.size()) != 2 * in[0].dim()) {
      throw ops::OpError("paddings must be rank×2");
    }
    std::vector<std::int64_t> pads;  // last dimension first
    for (std::int64_t d = in[0].dim() - 1; d >= 0; --d) {
      pads.push_back(p[2 * d]);
      pads.push_back(p[2 * d + 1]);
    }
    return V{torch::constant_pad_nd(in[0], pads, 0)};
  });
  return b;
}

// Every op with a kernel, by name.
const std::map<std::string, Builder>& builders() {
  static const std::map<std::string, Builder> table = [] {
    std::map<std::string, Builder> b = structural_ops();
    for (const auto& [op, f] : unary_ops()) {
      b[op] = plain(1, [f](V& in) { return V{f(in[0])}; });
    }
    for (const auto& [op, f] : binary_ops()) {
      b[op] = plain(2, [f](V& in) { return V{f(in[0], in[1])}; });
    }
    return b;
  }();
  return table;
}

}  // namespace

Kernel build_kernel(KernelSite& site) {
  const std::string& op = site.attrs.node().op;
  const auto found = builders().find(op);
  if (found == builders().end()) site.attrs.fail("unsupported op '" + op + "'");
  return found->second(site);
}

bool is_conv(const std::string& op) { return op == "Conv2D" || op == "_FusedConv2D"; }

bool is_depthwise(const std::string& op) {
  return op == "DepthwiseConv2dNative" || op == "FusedDepthwiseConv2dNative";
}

bool is_fused(const std::string& op) {
  return op == "_FusedConv2D" || op == "FusedDepthwiseConv2dNative";
}

torch::ScalarType scalar_type(DType d) {
  switch (d) {
    case DType::kFloat32:
      return torch::kFloat;
    case DType::kInt32:
      return torch::kInt;
    case DType::kInt64:
      return torch::kLong;
    case DType::kBool:
      return torch::kBool;
  }
  return torch::kFloat;
}

std::string shape_text(c10::IntArrayRef shape) {
  std::string s;
  for (std::size_t k = 0; k < shape.size(); ++k) s += (k ? "×" : "") + std::to_string(shape[k]);
  return s.empty() ? "scalar" : s;
}

}  // namespace wheelpose::learn
