#include "learn/graph_module.h"

#include <unzip.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/error.h"
#include "learn/graph_ops.h"
#include "learn/node_attrs.h"
#include "learn/op_kernels.h"
#include "learn/weights_file.h"

namespace wheelpose::learn {
namespace fs = std::filesystem;
using torch::Tensor;

namespace {

Tensor host_to_tensor(const HostTensor& h) {
  Tensor t = torch::empty(h.shape, torch::TensorOptions().dtype(scalar_type(h.dtype)));
  if (!h.data.empty()) std::memcpy(t.data_ptr(), h.data.data(), h.data.size());
  return t;
}

// How a constant is consumed: as a conv filter, a depthwise filter, a bias, or otherwise.
enum class Role { kNone, kConvFilter, kDepthwiseFilter, kBias, kOther };

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

// A .pt is a ZIP archive whose entries carry CRC-32s that LibTorch does not check: a damaged
// file would load as NaN weights and predict nulls. Reads every entry so minizip compares them.
// A file that is not a ZIP at all is left to pickle_load to refuse.
void verify_archive_checksums(const fs::path& path) {
  unzFile zip = unzOpen64(path.c_str());
  if (zip == nullptr) return;
  const std::unique_ptr<void, int (*)(unzFile)> close(zip, unzClose);
  std::vector<char> buffer(1 << 16);
  for (int status = unzGoToFirstFile(zip); status == UNZ_OK; status = unzGoToNextFile(zip)) {
    char name[512] = {};
    unzGetCurrentFileInfo64(zip, nullptr, name, sizeof name - 1, nullptr, 0, nullptr, 0);
    const auto damaged = [&](const std::string& what) {
      return Error(path.string() + ": damaged weights file: entry '" + name + "' " + what);
    };
    if (unzOpenCurrentFile(zip) != UNZ_OK) throw damaged("cannot be opened");
    int read = 0;
    while ((read = unzReadCurrentFile(zip, buffer.data(), static_cast<unsigned>(buffer.size()))) >
           0) {
    }
    const int closed = unzCloseCurrentFile(zip);
    if (read < 0) throw damaged("cannot be read");
    if (closed == UNZ_CRCERROR) throw damaged("fails its CRC-32 checksum");
  }
}

// The weights dict of a .pt written by save(); throws Error naming the file otherwise.
c10::impl::GenericDict read_weights_dict(const fs::path& path) {
  verify_archive_checksums(path);
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
  if (model_.inputs.size() != 1) {
    throw Error(model_.topology_path.string() + ": the graph has " +
                std::to_string(model_.inputs.size()) + " inputs; only single-input graphs run");
  }
  torch_layout_ = make_constants();
  const std::vector<bool>& torch_layout = torch_layout_;
  const std::size_t count = model_.nodes.size();
  kernels_.assign(count, nullptr);
  output_counts_.assign(count, 1);
  for (std::size_t n = 0; n < count; ++n) {
    const NodeAttrs attrs(model_, static_cast<int>(n));
    KernelSite site{attrs, constants_[n], torch_layout, channels_last_};
    kernels_[n] = build_kernel(site);
    output_counts_[n] = site.outputs;
  }
  check_references();
}

std::vector<bool> GraphModule::make_constants() {
  const std::vector<GraphNode>& nodes = model_.nodes;
  const std::size_t count = nodes.size();
  constants_.assign(count, Tensor());
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
        if (t.dim() != 4)
          NodeAttrs(model_, n).fail("a Conv2D filter must be 4-D [kh, kw, in, out]");
        t = t.permute({3, 2, 0, 1}).contiguous();
        torch_layout[n] = true;
      } else if (roles[n] == Role::kDepthwiseFilter) {
        if (t.dim() != 4)
          NodeAttrs(model_, n).fail("a depthwise filter must be 4-D [kh, kw, in, m]");
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
  return torch_layout;
}

void GraphModule::check_references() const {
  const std::vector<GraphNode>& nodes = model_.nodes;
  // Every consumer must ask for an output its producer makes.
  for (std::size_t n = 0; n < nodes.size(); ++n) {
    for (const TensorRef& in : nodes[n].inputs) {
      if (in.output < 0 || in.output >= output_counts_[in.node]) {
        NodeAttrs(model_, static_cast<int>(n))
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

torch::Tensor GraphModule::tf_value(const std::string& node_name) const {
  const int n = model_.find_node(node_name);
  if (n < 0 || model_.nodes[n].op != "Const") {
    throw Error(model_.topology_path.string() + ": '" + node_name + "' is not a constant");
  }
  const Tensor value = constants_[n].detach();
  if (!torch_layout_[n]) return value;
  const std::vector<std::int64_t>& tf_shape = model_.nodes[n].value->shape;
  // Conv2D [out, in, kh, kw] -> [kh, kw, in, out]; depthwise [in*m, 1, kh, kw] -> [kh, kw, in*m]
  // -> [kh, kw, in, m]. Both layouts are told apart by the constant's TF shape.
  const bool depthwise = value.size(1) == 1 && tf_shape[3] != value.size(0);
  if (depthwise) return value.squeeze(1).permute({1, 2, 0}).reshape(tf_shape).contiguous();
  return value.permute({2, 3, 1, 0}).contiguous();
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
    if (loaded.is_floating_point() && !torch::isfinite(loaded).all().item<bool>()) {
      throw Error(prefix + "parameter '" + node + "' holds NaN or infinity (a damaged file?)");
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
