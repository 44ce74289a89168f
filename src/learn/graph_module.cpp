#include "learn/graph_module.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/error.h"
#include "learn/graph_ops.h"
#include "learn/weights_file.h"

namespace wheelpose::learn {
namespace fs = std::filesystem;
using torch::Tensor;

namespace {

// Reads a node's attributes; a missing or mistyped one is an Error naming the node.
class Attrs {
 public:
  Attrs(const TfjsModel& model, int node) : model_(model), node_(node) {}
  [[noreturn]] void fail(const std::string& message) const {
    throw Error(model_.where(node_) + ": " + message);
  }
  const GraphNode& node() const { return model_.nodes[node_]; }

  const AttrValue* find(const std::string& key, AttrValue::Kind kind) const {
    const AttrValue* a = node().attr(key);
    if (a != nullptr && a->kind != kind) fail("attr '" + key + "' has the wrong type");
    return a;
  }
  std::int64_t i(const std::string& key, std::optional<std::int64_t> fallback = {}) const {
    if (const AttrValue* a = find(key, AttrValue::Kind::kInt)) return a->i;
    if (!fallback) fail("attr '" + key + "' is missing");
    return *fallback;
  }
  bool b(const std::string& key, bool fallback) const {
    const AttrValue* a = find(key, AttrValue::Kind::kBool);
    return a ? a->b : fallback;
  }
  double f(const std::string& key, double fallback) const {
    const AttrValue* a = find(key, AttrValue::Kind::kFloat);
    return a ? a->f : fallback;
  }
  std::string s(const std::string& key, std::optional<std::string> fallback = {}) const {
    if (const AttrValue* a = find(key, AttrValue::Kind::kString)) return a->s;
    if (!fallback) fail("attr '" + key + "' is missing");
    return *fallback;
  }
  std::vector<std::int64_t> ints(const std::string& key,
                                 std::optional<std::vector<std::int64_t>> fallback = {}) const {
    if (const AttrValue* a = find(key, AttrValue::Kind::kList)) return a->ints;
    if (!fallback) fail("attr '" + key + "' is missing");
    return *fallback;
  }
  std::vector<std::string> strings(const std::string& key) const {
    const AttrValue* a = find(key, AttrValue::Kind::kList);
    return a ? a->strings : std::vector<std::string>{};
  }
  std::optional<DType> type(const std::string& key) const {
    const AttrValue* a = find(key, AttrValue::Kind::kType);
    return a ? std::optional<DType>(a->type) : std::nullopt;
  }
  void inputs(std::size_t n) const { inputs(n, n); }
  void inputs(std::size_t min, std::size_t max) const {
    const std::size_t k = node().inputs.size();
    if (k < min || k > max) {
      fail("has " + std::to_string(k) + " inputs, expected " +
           (min == max ? std::to_string(min) : std::to_string(min) + ".." + std::to_string(max)));
    }
  }
  void nhwc() const {
    const std::string format = s("data_format", std::string("NHWC"));
    if (format != "NHWC") fail("data_format '" + format + "' is not supported (only NHWC)");
  }
  // A 4-vector attr [1, h, w, 1] (strides, dilations, ksize) as {h, w}.
  std::array<std::int64_t, 2> hw(const std::string& key, std::int64_t fallback) const {
    const std::vector<std::int64_t> v =
        ints(key, std::vector<std::int64_t>{1, fallback, fallback, 1});
    if (v.size() != 4 || v[0] != 1 || v[3] != 1 || v[1] < 1 || v[2] < 1) {
      fail("attr '" + key + "' must be [1, h, w, 1] with h, w >= 1");
    }
    return {v[1], v[2]};
  }
  ops::Padding padding() const {
    ops::Padding p;
    const std::string kind = s("padding");
    if (kind == "SAME") {
      p.kind = ops::Padding::Kind::kSame;
    } else if (kind == "VALID") {
      p.kind = ops::Padding::Kind::kValid;
    } else if (kind == "EXPLICIT") {
      p.kind = ops::Padding::Kind::kExplicit;
      const std::vector<std::int64_t> e = ints("explicit_paddings");
      if (e.size() != 8 || e[0] != 0 || e[1] != 0 || e[6] != 0 || e[7] != 0) {
        fail("explicit_paddings must be 8 values padding only H and W");
      }
      p.top = e[2];
      p.bottom = e[3];
      p.left = e[4];
      p.right = e[5];
    } else {
      fail("padding '" + kind + "' is not SAME, VALID or EXPLICIT");
    }
    return p;
  }

 private:
  const TfjsModel& model_;
  int node_;
};

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

Tensor host_to_tensor(const HostTensor& h) {
  Tensor t = torch::empty(h.shape, torch::TensorOptions().dtype(scalar_type(h.dtype)));
  if (!h.data.empty()) std::memcpy(t.data_ptr(), h.data.data(), h.data.size());
  return t;
}

// How a constant is consumed: as a conv filter, a depthwise filter, a bias, or otherwise.
enum class Role { kNone, kConvFilter, kDepthwiseFilter, kBias, kOther };

bool is_conv(const std::string& op) { return op == "Conv2D" || op == "_FusedConv2D"; }
bool is_depthwise(const std::string& op) {
  return op == "DepthwiseConv2dNative" || op == "FusedDepthwiseConv2dNative";
}
bool is_fused(const std::string& op) {
  return op == "_FusedConv2D" || op == "FusedDepthwiseConv2dNative";
}

Role role_of(const std::string& op, std::size_t input) {
  if (input == 1 && is_conv(op)) return Role::kConvFilter;
  if (input == 1 && is_depthwise(op)) return Role::kDepthwiseFilter;
  if (input >= 2 && is_fused(op)) return Role::kBias;
  if (input == 1 && op == "BiasAdd") return Role::kBias;
  return Role::kOther;
}

std::string first_line(const std::string& s) {
  const std::size_t nl = s.find('\n');
  return nl == std::string::npos ? s : s.substr(0, nl);
}

std::string shape_text(c10::IntArrayRef shape) {
  std::string s;
  for (std::size_t k = 0; k < shape.size(); ++k) s += (k ? "×" : "") + std::to_string(shape[k]);
  return s.empty() ? "scalar" : s;
}

// The weights dict of a .pt written by save(); throws Error naming the file otherwise.
c10::impl::GenericDict read_weights_dict(const fs::path& path) {
  const std::string bytes = read_file(path);
  c10::IValue value;
  try {
    value = torch::pickle_load(std::vector<char>(bytes.begin(), bytes.end()));
  } catch (const c10::Error& e) {
    throw Error(path.string() + ": not a weights file (" + first_line(e.what_without_backtrace()) +
                ")");
  }
  auto bad = [&](const std::string& why) -> Error {
    return Error(path.string() + ": not a " + kWeightsFormat + " file (" + why + ")");
  };
  if (!value.isGenericDict()) throw bad("not a dict");
  c10::impl::GenericDict dict = value.toGenericDict();
  auto get = [&](const char* key) -> c10::IValue {
    auto it = dict.find(c10::IValue(std::string(key)));
    if (it == dict.end()) throw bad(std::string("no '") + key + "'");
    return it->value();
  };
  const c10::IValue format = get("format");
  if (!format.isString() || format.toStringRef() != kWeightsFormat) throw bad("wrong format");
  if (!get("model").isString()) throw bad("'model' is not a string");
  if (!get("parameters").isGenericDict()) throw bad("'parameters' is not a dict");
  return dict;
}

}  // namespace

std::string weights_model_name(const fs::path& path) {
  return read_weights_dict(path).at(c10::IValue(std::string("model"))).toStringRef();
}

GraphModule::GraphModule(const fs::path& topology_json)
    : GraphModule(load_tfjs_model(topology_json)) {}

GraphModule::GraphModule(TfjsModel model) : model_(std::move(model)) { compile(); }

void GraphModule::compile() {
  const std::vector<GraphNode>& nodes = model_.nodes;
  const std::size_t count = nodes.size();
  kernels_.assign(count, nullptr);
  output_counts_.assign(count, 1);
  constants_.assign(count, Tensor());

  if (model_.inputs.size() != 1) {
    throw Error(model_.topology_path.string() + ": the graph has " +
                std::to_string(model_.inputs.size()) + " inputs; only single-input graphs run");
  }

  // Roles of each constant, to choose the trainable ones and their layout.
  std::vector<Role> roles(count, Role::kNone);
  for (const GraphNode& node : nodes) {
    for (std::size_t k = 0; k < node.inputs.size(); ++k) {
      Role& r = roles[node.inputs[k].node];
      const Role use = role_of(node.op, k);
      r = (r == Role::kNone || r == use) ? use : Role::kOther;
    }
  }
  std::vector<bool> torch_layout(count, false);  // filter stored as torch expects it
  std::set<std::string> used_names;
  for (std::size_t n = 0; n < count; ++n) {
    const GraphNode& node = nodes[n];
    if (node.op != "Const") continue;
    Tensor t = host_to_tensor(*node.value);
    const bool trainable = t.scalar_type() == torch::kFloat &&
                           (roles[n] == Role::kConvFilter || roles[n] == Role::kDepthwiseFilter ||
                            roles[n] == Role::kBias);
    if (trainable) {
      if (roles[n] == Role::kConvFilter) {
        if (t.dim() != 4) Attrs(model_, n).fail("a Conv2D filter must be 4-D [kh, kw, in, out]");
        t = t.permute({3, 2, 0, 1}).contiguous();
        torch_layout[n] = true;
      } else if (roles[n] == Role::kDepthwiseFilter) {
        if (t.dim() != 4) Attrs(model_, n).fail("a depthwise filter must be 4-D [kh, kw, in, m]");
        t = ops::depthwise_filter_to_torch(t).contiguous();
        torch_layout[n] = true;
      }
      std::string name = node.name;
      std::replace(name.begin(), name.end(), '.', '_');
      if (used_names.contains(name)) {
        int suffix = 2;
        while (used_names.contains(name + "_" + std::to_string(suffix))) ++suffix;
        name += "_" + std::to_string(suffix);
      }
      used_names.insert(name);
      t = register_parameter(name, t, /*requires_grad=*/true);
      param_by_node_.emplace(node.name, name);
      parameter_nodes_.push_back(node.name);
    }
    constants_[n] = t;
  }

  for (std::size_t n = 0; n < count; ++n) {
    const GraphNode& node = nodes[n];
    const std::string& op = node.op;
    const Attrs a(model_, static_cast<int>(n));
    Kernel& k = kernels_[n];
    using V = std::vector<Tensor>;
    auto unary = [&](Tensor (*f)(const Tensor&)) {
      a.inputs(1);
      k = [f](V& in) { return V{f(in[0])}; };
    };
    auto binary = [&](Tensor (*f)(const Tensor&, const Tensor&)) {
      a.inputs(2);
      k = [f](V& in) { return V{f(in[0], in[1])}; };
    };

    if (op == "Const") {
      a.inputs(0);
      k = [t = constants_[n]](V&) { return V{t}; };
    } else if (op == "Placeholder") {
      a.inputs(0);
      k = nullptr;  // forward() supplies the input
    } else if (op == "Identity" || op == "Snapshot") {
      a.inputs(1);
      k = [](V& in) { return V{in[0]}; };
    } else if (op == "StopGradient") {
      unary([](const Tensor& x) { return x.detach(); });
    } else if (op == "NoOp") {
      output_counts_[n] = 0;
      k = [](V&) { return V{}; };
    } else if (is_conv(op) || is_depthwise(op)) {
      ops::ConvSpec spec;
      spec.depthwise = is_depthwise(op);
      a.nhwc();
      const auto strides = a.hw("strides", 1);
      const auto dilations = a.hw("dilations", 1);
      spec.stride = {strides[0], strides[1]};
      spec.dilation = {dilations[0], dilations[1]};
      spec.padding = a.padding();
      std::size_t args = 0;
      if (is_fused(op)) {
        args = static_cast<std::size_t>(a.i("num_args"));
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
                 " is not supported (BiasAdd then Relu, Relu6, Elu, LeakyRelu, Sigmoid, Tanh or "
                 "Prelu)");
        }
      } else {
        a.inputs(2);
      }
      spec.filter_in_torch_layout = torch_layout[node.inputs[1].node];
      k = [this, spec](V& in) {
        const Tensor bias = spec.bias ? in[2] : Tensor();
        const Tensor prelu =
            spec.activation == ops::Activation::kPrelu ? in[spec.bias ? 3 : 2] : Tensor();
        return V{ops::conv2d_nhwc(in[0], in[1], bias, prelu, spec, channels_last_)};
      };
    } else if (op == "BiasAdd") {
      a.inputs(2);
      a.nhwc();
      k = [](V& in) { return V{in[0] + in[1]}; };
    } else if (op == "MaxPool") {
      a.inputs(1);
      a.nhwc();
      const auto ksize = a.hw("ksize", 1);
      const auto strides = a.hw("strides", 1);
      const ops::Padding padding = a.padding();
      k = [this, ksize, strides, padding](V& in) {
        return V{ops::max_pool_nhwc(in[0], {ksize[0], ksize[1]}, {strides[0], strides[1]}, padding,
                                    channels_last_)};
      };
    } else if (op == "ResizeBilinear") {
      a.inputs(2);
      const bool align = a.b("align_corners", false);
      const bool half = a.b("half_pixel_centers", false);
      if (align && half) a.fail("align_corners and half_pixel_centers cannot both be true");
      k = [align, half](V& in) {
        const std::vector<std::int64_t> size = ops::int_values(in[1]);
        if (size.size() != 2 || size[0] <= 0 || size[1] <= 0) {
          throw ops::OpError("size must be 2 positive values");
        }
        return V{ops::resize_bilinear(in[0], size[0], size[1], align, half)};
      };
    } else if (op == "Cast") {
      a.inputs(1);
      const std::optional<DType> dst = a.type("DstT");
      if (!dst) a.fail("attr 'DstT' is missing");
      k = [dst = scalar_type(*dst)](V& in) { return V{ops::cast(in[0], dst)}; };
    } else if (op == "Add" || op == "AddV2") {
      binary([](const Tensor& x, const Tensor& y) { return x + y; });
    } else if (op == "Sub") {
      binary([](const Tensor& x, const Tensor& y) { return x - y; });
    } else if (op == "Mul") {
      binary([](const Tensor& x, const Tensor& y) { return x * y; });
    } else if (op == "RealDiv") {
      binary([](const Tensor& x, const Tensor& y) { return x / y; });
    } else if (op == "FloorDiv") {
      binary(ops::floor_div);
    } else if (op == "Maximum") {
      binary([](const Tensor& x, const Tensor& y) { return torch::maximum(x, y); });
    } else if (op == "Minimum") {
      binary([](const Tensor& x, const Tensor& y) { return torch::minimum(x, y); });
    } else if (op == "SquaredDifference") {
      binary([](const Tensor& x, const Tensor& y) {
        const Tensor d = x - y;
        return d * d;
      });
    } else if (op == "AddN") {
      a.inputs(1, SIZE_MAX);
      k = [](V& in) {
        Tensor sum = in[0];
        for (std::size_t j = 1; j < in.size(); ++j) sum = sum + in[j];
        return V{sum};
      };
    } else if (op == "Abs") {
      unary([](const Tensor& x) { return x.abs(); });
    } else if (op == "Neg") {
      unary([](const Tensor& x) { return -x; });
    } else if (op == "Exp") {
      unary([](const Tensor& x) { return x.exp(); });
    } else if (op == "Log") {
      unary([](const Tensor& x) { return x.log(); });
    } else if (op == "Sqrt") {
      unary([](const Tensor& x) { return x.sqrt(); });
    } else if (op == "Rsqrt") {
      unary([](const Tensor& x) { return x.rsqrt(); });
    } else if (op == "Square") {
      unary([](const Tensor& x) { return x * x; });
    } else if (op == "Reciprocal") {
      unary([](const Tensor& x) { return x.reciprocal(); });
    } else if (op == "Floor") {
      unary([](const Tensor& x) { return x.floor(); });
    } else if (op == "Sigmoid") {
      unary([](const Tensor& x) { return x.sigmoid(); });
    } else if (op == "Tanh") {
      unary([](const Tensor& x) { return x.tanh(); });
    } else if (op == "Relu") {
      unary([](const Tensor& x) { return x.relu(); });
    } else if (op == "Relu6") {
      unary([](const Tensor& x) { return x.clamp(0, 6); });
    } else if (op == "Equal") {
      binary([](const Tensor& x, const Tensor& y) { return x.eq(y); });
    } else if (op == "NotEqual") {
      binary([](const Tensor& x, const Tensor& y) { return x.ne(y); });
    } else if (op == "Less") {
      binary([](const Tensor& x, const Tensor& y) { return x.lt(y); });
    } else if (op == "LessEqual") {
      binary([](const Tensor& x, const Tensor& y) { return x.le(y); });
    } else if (op == "Greater") {
      binary([](const Tensor& x, const Tensor& y) { return x.gt(y); });
    } else if (op == "GreaterEqual") {
      binary([](const Tensor& x, const Tensor& y) { return x.ge(y); });
    } else if (op == "LogicalAnd") {
      binary([](const Tensor& x, const Tensor& y) { return x.logical_and(y); });
    } else if (op == "LogicalOr") {
      binary([](const Tensor& x, const Tensor& y) { return x.logical_or(y); });
    } else if (op == "LogicalNot") {
      unary([](const Tensor& x) { return x.logical_not(); });
    } else if (op == "Select") {
      a.inputs(3);
      k = [](V& in) { return V{ops::select_v1(in[0], in[1], in[2])}; };
    } else if (op == "SelectV2") {
      a.inputs(3);
      k = [](V& in) { return V{torch::where(in[0], in[1], in[2])}; };
    } else if (op == "Sum" || op == "Max" || op == "Min" || op == "Mean") {
      a.inputs(2);
      const bool keep = a.b("keep_dims", false);
      const ops::Reduction r = op == "Sum"   ? ops::Reduction::kSum
                               : op == "Max" ? ops::Reduction::kMax
                               : op == "Min" ? ops::Reduction::kMin
                                             : ops::Reduction::kMean;
      k = [r, keep](V& in) { return V{ops::reduce(in[0], ops::int_values(in[1]), r, keep)}; };
    } else if (op == "ArgMax") {
      a.inputs(2);
      const torch::ScalarType out = scalar_type(a.type("output_type").value_or(DType::kInt64));
      k = [out](V& in) { return V{ops::arg_max(in[0], ops::int_value(in[1])).to(out)}; };
    } else if (op == "TopKV2") {
      a.inputs(2);
      output_counts_[n] = 2;
      k = [](V& in) {
        auto [values, indices] = ops::top_k(in[0], ops::int_value(in[1]));
        return V{values, indices};
      };
    } else if (op == "GatherNd") {
      a.inputs(2);
      k = [](V& in) { return V{ops::gather_nd(in[0], in[1])}; };
    } else if (op == "Shape") {
      a.inputs(1);
      const torch::ScalarType out = scalar_type(a.type("out_type").value_or(DType::kInt32));
      k = [out](V& in) { return V{torch::tensor(in[0].sizes().vec(), torch::kLong).to(out)}; };
    } else if (op == "Size") {
      a.inputs(1);
      const torch::ScalarType out = scalar_type(a.type("out_type").value_or(DType::kInt32));
      k = [out](V& in) { return V{torch::scalar_tensor(in[0].numel(), torch::kLong).to(out)}; };
    } else if (op == "Reshape") {
      a.inputs(2);
      k = [](V& in) { return V{in[0].reshape(ops::int_values(in[1]))}; };
    } else if (op == "Squeeze") {
      a.inputs(1);
      const std::vector<std::int64_t> dims = a.ints("squeeze_dims", std::vector<std::int64_t>{});
      k = [dims](V& in) { return V{ops::squeeze_dims(in[0], dims)}; };
    } else if (op == "ExpandDims") {
      a.inputs(2);
      k = [](V& in) {
        std::int64_t dim = ops::int_value(in[1]);
        const std::int64_t rank = in[0].dim();
        if (dim < -rank - 1 || dim > rank) throw ops::OpError("dim out of range");
        if (dim < 0) dim += rank + 1;
        return V{in[0].unsqueeze(dim)};
      };
    } else if (op == "StridedSlice") {
      a.inputs(4);
      ops::SliceMasks m;
      m.begin = a.i("begin_mask", 0);
      m.end = a.i("end_mask", 0);
      m.ellipsis = a.i("ellipsis_mask", 0);
      m.new_axis = a.i("new_axis_mask", 0);
      m.shrink_axis = a.i("shrink_axis_mask", 0);
      k = [m](V& in) {
        return V{ops::strided_slice(in[0], ops::int_values(in[1]), ops::int_values(in[2]),
                                    ops::int_values(in[3]), m)};
      };
    } else if (op == "Pack") {
      a.inputs(1, SIZE_MAX);
      const std::int64_t axis = a.i("axis", 0);
      k = [axis](V& in) {
        const std::int64_t rank = in[0].dim() + 1;
        if (axis < -rank || axis >= rank) throw ops::OpError("axis out of range");
        return V{torch::stack(in, axis < 0 ? axis + rank : axis)};
      };
    } else if (op == "Unpack") {
      a.inputs(1);
      const std::int64_t num = a.i("num");
      const std::int64_t axis = a.i("axis", 0);
      output_counts_[n] = static_cast<int>(num);
      k = [axis, num](V& in) {
        const std::int64_t rank = in[0].dim();
        if (axis < -rank || axis >= rank) throw ops::OpError("axis out of range");
        const std::vector<Tensor> parts = in[0].unbind(axis < 0 ? axis + rank : axis);
        if (static_cast<std::int64_t>(parts.size()) != num) {
          throw ops::OpError("the axis has " + std::to_string(parts.size()) + " entries, num is " +
                             std::to_string(num));
        }
        return parts;
      };
    } else if (op == "ConcatV2") {
      a.inputs(2, SIZE_MAX);
      k = [](V& in) {
        const std::int64_t axis = ops::int_value(in.back());
        in.pop_back();
        return V{torch::cat(in, axis)};
      };
    } else if (op == "Split") {
      a.inputs(2);
      const std::int64_t num = a.i("num_split");
      output_counts_[n] = static_cast<int>(num);
      k = [num](V& in) {
        std::int64_t axis = ops::int_value(in[0]);
        const Tensor& x = in[1];
        if (axis < 0) axis += x.dim();
        if (axis < 0 || axis >= x.dim() || num <= 0 || x.size(axis) % num != 0) {
          throw ops::OpError("cannot split dimension " + std::to_string(axis) + " of " +
                             shape_text(x.sizes()) + " into " + std::to_string(num));
        }
        return x.split(x.size(axis) / num, axis);
      };
    } else if (op == "Tile") {
      a.inputs(2);
      k = [](V& in) {
        const std::vector<std::int64_t> reps = ops::int_values(in[1]);
        if (static_cast<std::int64_t>(reps.size()) != in[0].dim()) {
          throw ops::OpError("multiples has " + std::to_string(reps.size()) +
                             " values for a rank-" + std::to_string(in[0].dim()) + " tensor");
        }
        return V{in[0].repeat(reps)};
      };
    } else if (op == "Fill") {
      a.inputs(2);
      k = [](V& in) {
        if (in[1].numel() != 1) throw ops::OpError("value must be a scalar");
        return V{in[1].reshape({}).expand(ops::int_values(in[0])).contiguous()};
      };
    } else if (op == "Range") {
      a.inputs(3);
      k = [](V& in) { return V{ops::range(in[0], in[1], in[2])}; };
    } else if (op == "Transpose") {
      a.inputs(2);
      k = [](V& in) { return V{in[0].permute(ops::int_values(in[1]))}; };
    } else if (op == "Pad") {
      a.inputs(2);
      k = [](V& in) {
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
      };
    } else {
      a.fail("unsupported op '" + op + "'");
    }
  }

  // Every consumer must ask for an output its producer makes.
  for (std::size_t n = 0; n < count; ++n) {
    for (const TensorRef& in : nodes[n].inputs) {
      if (in.output < 0 || in.output >= output_counts_[in.node]) {
        Attrs(model_, static_cast<int>(n))
            .fail("input '" + model_.tensor_name(in) + "' does not exist (" + nodes[in.node].op +
                  " has " + std::to_string(output_counts_[in.node]) + " outputs)");
      }
    }
  }
  for (const SignatureTensor& out : model_.outputs) {
    if (out.ref.output >= output_counts_[out.ref.node]) {
      throw Error(model_.topology_path.string() + ": signature output '" + out.name +
                  "' does not exist");
    }
  }
}

std::vector<std::string> GraphModule::output_names() const {
  std::vector<std::string> names;
  for (const SignatureTensor& out : model_.outputs) names.push_back(out.name);
  return names;
}

torch::Tensor GraphModule::parameter(const std::string& node_name) const {
  auto it = param_by_node_.find(node_name);
  if (it == param_by_node_.end()) {
    throw Error(model_.topology_path.string() + ": node '" + node_name +
                "' is not a trainable parameter");
  }
  return named_parameters(/*recurse=*/false)[it->second];
}

void GraphModule::set_capture(std::vector<std::string> names) {
  plan_for(names, true);  // validates
  capture_ = std::move(names);
}

const GraphModule::Plan& GraphModule::plan_for(const std::vector<std::string>& capture,
                                               bool with_outputs) {
  std::string key = with_outputs ? "outputs\n" : "only\n";
  for (const std::string& name : capture) key += name + '\n';
  if (auto it = plans_.find(key); it != plans_.end()) return it->second;

  Plan plan;
  for (const SignatureTensor& out : model_.outputs) {
    if (!with_outputs) break;
    plan.names.push_back(out.name);
    plan.refs.push_back(out.ref);
  }
  for (const std::string& name : capture) {
    const TensorRef ref = model_.resolve(name);
    if (ref.output >= output_counts_[ref.node]) {
      throw Error(model_.topology_path.string() + ": cannot capture '" + name +
                  "': " + model_.nodes[ref.node].op + " node has " +
                  std::to_string(output_counts_[ref.node]) + " outputs");
    }
    plan.names.push_back(name);
    plan.refs.push_back(ref);
  }
  const std::size_t count = model_.nodes.size();
  std::vector<bool> needed(count, false);
  std::vector<int> stack;
  for (const TensorRef& ref : plan.refs) stack.push_back(ref.node);
  while (!stack.empty()) {
    const int n = stack.back();
    stack.pop_back();
    if (needed[n]) continue;
    needed[n] = true;
    for (const TensorRef& in : model_.nodes[n].inputs) stack.push_back(in.node);
    for (int c : model_.nodes[n].control_inputs) stack.push_back(c);
  }
  std::vector<int> last_use(count, -1);
  for (std::size_t n = 0; n < count; ++n) {
    if (!needed[n]) continue;
    const int step = static_cast<int>(plan.steps.size());
    plan.steps.push_back(static_cast<int>(n));
    for (const TensorRef& in : model_.nodes[n].inputs) last_use[in.node] = step;
  }
  std::vector<bool> kept(count, false);
  for (const TensorRef& ref : plan.refs) kept[ref.node] = true;
  plan.release.assign(plan.steps.size(), {});
  for (std::size_t n = 0; n < count; ++n) {
    if (last_use[n] >= 0 && !kept[n]) plan.release[last_use[n]].push_back(static_cast<int>(n));
  }
  return plans_.emplace(key, std::move(plan)).first->second;
}

TensorMap GraphModule::forward(const torch::Tensor& input) { return forward(input, capture_); }

TensorMap GraphModule::forward(const torch::Tensor& input,
                               const std::vector<std::string>& capture) {
  return run(input, plan_for(capture, true), false);
}

TensorMap GraphModule::forward_only(const torch::Tensor& input,
                                    const std::vector<std::string>& names) {
  return run(input, plan_for(names, false), true);
}

TensorMap GraphModule::run(const torch::Tensor& input, const Plan& plan, bool any_batch) {
  const SignatureTensor& sig = model_.inputs[0];
  const GraphNode& placeholder = model_.nodes[sig.ref.node];
  std::vector<std::int64_t> expected = sig.shape;
  if (const AttrValue* s = placeholder.attr("shape"); s && s->kind == AttrValue::Kind::kShape) {
    expected = s->shape;
  }
  bool fits = input.defined() &&
              (expected.empty() || input.dim() == static_cast<std::int64_t>(expected.size()));
  for (std::size_t d = 0; fits && d < expected.size(); ++d) {
    fits = expected[d] < 0 || expected[d] == input.size(static_cast<std::int64_t>(d)) ||
           (d == 0 && any_batch);
  }
  if (!fits) {
    std::string want;
    for (std::size_t d = 0; d < expected.size(); ++d) {
      want += (d ? "×" : "") + (expected[d] < 0 ? std::string("?") : std::to_string(expected[d]));
    }
    throw Error(model_.topology_path.string() + ": input must be " + want + " (NHWC), got " +
                (input.defined() ? shape_text(input.sizes()) : std::string("nothing")));
  }
  Tensor x = input;
  if (x.is_floating_point()) {
    x = x.to(torch::kFloat);
  } else {
    const AttrValue* d = placeholder.attr("dtype");
    x = x.to(d && d->kind == AttrValue::Kind::kType ? scalar_type(d->type) : torch::kInt);
  }

  std::vector<std::vector<Tensor>> values(model_.nodes.size());
  std::vector<Tensor> args;
  for (std::size_t step = 0; step < plan.steps.size(); ++step) {
    const int n = plan.steps[step];
    const GraphNode& node = model_.nodes[n];
    if (node.op == "Placeholder") {
      if (n != sig.ref.node) {
        throw Error(model_.where(n) + ": a second input is not supported");
      }
      values[n] = {x};
    } else {
      args.clear();
      for (const TensorRef& in : node.inputs) args.push_back(values[in.node][in.output]);
      try {
        values[n] = kernels_[n](args);
      } catch (const ops::OpError& e) {
        throw Error(model_.where(n) + ": " + e.what(), ErrorKind::kFailure);
      } catch (const c10::Error& e) {
        throw Error(model_.where(n) + ": " + first_line(e.what_without_backtrace()),
                    ErrorKind::kFailure);
      } catch (const Error&) {
        throw;
      } catch (const std::exception& e) {  // some ATen checks throw std::runtime_error
        throw Error(model_.where(n) + ": " + first_line(e.what()), ErrorKind::kFailure);
      }
      WHEELPOSE_CHECK(static_cast<int>(values[n].size()) == output_counts_[n]);
    }
    for (int r : plan.release[step]) values[r].clear();
  }
  args.clear();
  TensorMap result;
  for (std::size_t k = 0; k < plan.names.size(); ++k) {
    result[plan.names[k]] = values[plan.refs[k].node][plan.refs[k].output];
  }
  return result;
}

void GraphModule::save(const fs::path& path) const {
  c10::Dict<std::string, Tensor> params;
  for (const std::string& node : parameter_nodes_) {
    params.insert(node, constants_[model_.index.at(node)].detach().contiguous());
  }
  c10::impl::GenericDict dict(c10::StringType::get(), c10::AnyType::get());
  dict.insert(std::string("format"), std::string(kWeightsFormat));
  dict.insert(std::string("version"), static_cast<std::int64_t>(1));
  dict.insert(std::string("model"), model_.name());
  dict.insert(std::string("parameters"), params);
  const std::vector<char> bytes = torch::pickle_save(c10::IValue(dict));
  write_file_atomic(path, std::string_view(bytes.data(), bytes.size()));
}

void GraphModule::load(const fs::path& path) {
  const c10::impl::GenericDict dict = read_weights_dict(path);
  const std::string model = dict.at(c10::IValue(std::string("model"))).toStringRef();
  const std::string prefix = path.string() + ": ";
  if (model != model_.name()) {
    throw Error(prefix + "weights of model '" + model + "', not of " +
                model_.topology_path.filename().string());
  }
  const c10::impl::GenericDict params =
      dict.at(c10::IValue(std::string("parameters"))).toGenericDict();
  std::vector<std::pair<Tensor, Tensor>> copies;
  std::string missing, wrong_shape, unknown;
  int missing_count = 0, wrong_count = 0, unknown_count = 0;
  for (const std::string& node : parameter_nodes_) {
    auto it = params.find(c10::IValue(node));
    if (it == params.end() || !it->value().isTensor()) {
      if (missing_count++ == 0) missing = node;
      continue;
    }
    const Tensor loaded = it->value().toTensor();
    const Tensor& target = constants_[model_.index.at(node)];
    if (loaded.sizes() != target.sizes() || loaded.scalar_type() != target.scalar_type()) {
      if (wrong_count++ == 0) {
        wrong_shape = "'" + node + "' is " + shape_text(loaded.sizes()) + ", the model's " +
                      shape_text(target.sizes());
      }
      continue;
    }
    copies.emplace_back(target, loaded);
  }
  for (const auto& entry : params) {
    const std::string& key = entry.key().toStringRef();
    if (!param_by_node_.contains(key) && unknown_count++ == 0) unknown = key;
  }
  if (missing_count + wrong_count + unknown_count > 0) {
    std::string why;
    if (missing_count) {
      why += std::to_string(missing_count) + " parameters missing (first '" + missing + "')";
    }
    if (unknown_count) {
      why += std::string(why.empty() ? "" : ", ") + std::to_string(unknown_count) +
             " unknown (first '" + unknown + "')";
    }
    if (wrong_count) {
      why += std::string(why.empty() ? "" : ", ") + std::to_string(wrong_count) +
             " of another shape (first " + wrong_shape + ")";
    }
    throw Error(prefix + "weights do not fit " + model_.topology_path.filename().string() + ": " +
                why);
  }
  torch::NoGradGuard no_grad;
  for (auto& [target, loaded] : copies) target.copy_(loaded);
}

}  // namespace wheelpose::learn
