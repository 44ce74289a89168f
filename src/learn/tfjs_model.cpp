#include "learn/tfjs_model.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>

#include "core/atomic_file.h"
#include "core/error.h"

namespace wheelpose::learn {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

[[noreturn]] void fail(const fs::path& file, const std::string& message) {
  throw Error(file.string() + ": " + message);
}

std::string base64_decode(const fs::path& file, const std::string& key, std::string_view in) {
  static const std::array<int, 256> table = [] {
    std::array<int, 256> t{};
    t.fill(-1);
    const char* alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    for (int i = 0; i < 64; ++i) t[static_cast<unsigned char>(alphabet[i])] = i;
    t['-'] = 62;  // the URL-safe alphabet too
    t['_'] = 63;
    return t;
  }();
  std::string out;
  std::uint32_t buffer = 0;
  int bits = 0;
  for (char c : in) {
    if (c == '=' || c == '\n' || c == '\r') continue;
    const int v = table[static_cast<unsigned char>(c)];
    if (v < 0) fail(file, key + ": invalid base64 character '" + std::string(1, c) + "'");
    buffer = (buffer << 6) | static_cast<std::uint32_t>(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<char>((buffer >> bits) & 0xFF));
    }
  }
  return out;
}

// Reads JSON values, turning every missing key and wrong type into one line naming the key.
class Reader {
 public:
  explicit Reader(fs::path file) : file_(std::move(file)) {}
  const fs::path& file() const { return file_; }

  [[noreturn]] void fail_at(const std::string& key, const std::string& message) const {
    fail(file_, "key '" + key + "': " + message);
  }
  const json& need(const json& object, const char* name, const std::string& key) const {
    if (!object.is_object()) fail_at(key, "expected an object");
    auto it = object.find(name);
    if (it == object.end()) fail_at(key, std::string("missing key '") + name + "'");
    return *it;
  }
  const json* find(const json& object, const char* name) const {
    if (!object.is_object()) return nullptr;
    auto it = object.find(name);
    return it == object.end() ? nullptr : &*it;
  }
  const json& array(const json& value, const std::string& key) const {
    if (!value.is_array()) fail_at(key, "expected an array");
    return value;
  }
  std::string string(const json& value, const std::string& key) const {
    if (!value.is_string()) fail_at(key, "expected a string");
    return value.get<std::string>();
  }
  // Protobuf JSON writes int64 as strings; accept numbers too.
  std::int64_t int64(const json& value, const std::string& key) const {
    if (value.is_number_integer()) return value.get<std::int64_t>();
    if (value.is_string()) {
      const std::string s = value.get<std::string>();
      try {
        std::size_t used = 0;
        const long long v = std::stoll(s, &used);
        if (used == s.size()) return v;
      } catch (const std::exception&) {
      }
    }
    fail_at(key, "expected an integer, got " + value.dump());
  }
  double number(const json& value, const std::string& key) const {
    if (value.is_number()) return value.get<double>();
    if (value.is_string()) {
      const std::string s = value.get<std::string>();
      if (s == "NaN") return std::nan("");
      if (s == "Infinity") return INFINITY;
      if (s == "-Infinity") return -INFINITY;
    }
    fail_at(key, "expected a number, got " + value.dump());
  }
  bool boolean(const json& value, const std::string& key) const {
    if (!value.is_boolean()) fail_at(key, "expected true or false");
    return value.get<bool>();
  }
  std::vector<std::int64_t> shape(const json& tensor_shape, const std::string& key) const {
    std::vector<std::int64_t> dims;
    if (!tensor_shape.is_object()) fail_at(key, "expected a tensorShape object");
    if (const json* dim = find(tensor_shape, "dim")) {
      array(*dim, key + ".dim");
      for (std::size_t d = 0; d < dim->size(); ++d) {
        const std::string dkey = key + ".dim[" + std::to_string(d) + "]";
        const json* size = find((*dim)[d], "size");
        dims.push_back(size == nullptr ? 0 : int64(*size, dkey + ".size"));
      }
    }
    return dims;
  }

 private:
  fs::path file_;
};

std::optional<DType> dtype_from_tf(std::string_view s) {
  if (s == "DT_FLOAT") return DType::kFloat32;
  if (s == "DT_INT32") return DType::kInt32;
  if (s == "DT_INT64") return DType::kInt64;
  if (s == "DT_BOOL") return DType::kBool;
  return std::nullopt;
}

std::optional<DType> dtype_from_manifest(std::string_view s) {
  if (s == "float32") return DType::kFloat32;
  if (s == "int32") return DType::kInt32;
  if (s == "int64") return DType::kInt64;
  if (s == "bool") return DType::kBool;
  return std::nullopt;
}

std::int64_t element_count(const std::vector<std::int64_t>& shape) {
  std::int64_t n = 1;
  for (std::int64_t d : shape) n *= d;
  return n;
}

AttrValue parse_attr(const Reader& r, const json& value, const std::string& key) {
  AttrValue a;
  if (!value.is_object() || value.empty()) r.fail_at(key, "expected an AttrValue object");
  if (const json* v = r.find(value, "i")) {
    a.kind = AttrValue::Kind::kInt;
    a.i = r.int64(*v, key + ".i");
  } else if (const json* v = r.find(value, "f")) {
    a.kind = AttrValue::Kind::kFloat;
    a.f = r.number(*v, key + ".f");
  } else if (const json* v = r.find(value, "b")) {
    a.kind = AttrValue::Kind::kBool;
    a.b = r.boolean(*v, key + ".b");
  } else if (const json* v = r.find(value, "s")) {
    a.kind = AttrValue::Kind::kString;
    a.s = base64_decode(r.file(), key + ".s", r.string(*v, key + ".s"));
  } else if (const json* v = r.find(value, "type")) {
    a.kind = AttrValue::Kind::kType;
    const std::string t = r.string(*v, key + ".type");
    const std::optional<DType> d = dtype_from_tf(t);
    if (!d) r.fail_at(key + ".type", "unknown dtype '" + t + "'");
    a.type = *d;
  } else if (const json* v = r.find(value, "shape")) {
    a.kind = AttrValue::Kind::kShape;
    a.shape = r.shape(*v, key + ".shape");
  } else if (r.find(value, "tensor") != nullptr) {
    a.kind = AttrValue::Kind::kTensor;  // Const values: read by read_inline_tensor
  } else if (const json* v = r.find(value, "list")) {
    a.kind = AttrValue::Kind::kList;
    const std::string lkey = key + ".list";
    if (!v->is_object()) r.fail_at(lkey, "expected an object");
    if (const json* l = r.find(*v, "i")) {
      r.array(*l, lkey + ".i");
      for (std::size_t k = 0; k < l->size(); ++k) {
        a.ints.push_back(r.int64((*l)[k], lkey + ".i[" + std::to_string(k) + "]"));
      }
    }
    if (const json* l = r.find(*v, "f")) {
      r.array(*l, lkey + ".f");
      for (std::size_t k = 0; k < l->size(); ++k) {
        a.floats.push_back(r.number((*l)[k], lkey + ".f[" + std::to_string(k) + "]"));
      }
    }
    if (const json* l = r.find(*v, "s")) {
      r.array(*l, lkey + ".s");
      for (std::size_t k = 0; k < l->size(); ++k) {
        const std::string skey = lkey + ".s[" + std::to_string(k) + "]";
        a.strings.push_back(base64_decode(r.file(), skey, r.string((*l)[k], skey)));
      }
    }
  } else {
    r.fail_at(key, "unsupported AttrValue " + value.dump().substr(0, 80));
  }
  return a;
}

template <typename T>
void append_value(std::vector<std::byte>& data, T v) {
  const auto* p = reinterpret_cast<const std::byte*>(&v);
  data.insert(data.end(), p, p + sizeof(T));
}

// A Const's value written into the topology (attr.value.tensor) instead of the manifest.
std::optional<HostTensor> read_inline_tensor(const Reader& r, const json& tensor,
                                             const std::string& key) {
  HostTensor t;
  const std::string dt = r.string(r.need(tensor, "dtype", key), key + ".dtype");
  const std::optional<DType> d = dtype_from_tf(dt);
  if (!d) r.fail_at(key + ".dtype", "unknown dtype '" + dt + "'");
  t.dtype = *d;
  if (const json* shape = r.find(tensor, "tensorShape")) {
    t.shape = r.shape(*shape, key + ".tensorShape");
  }
  const std::int64_t n = element_count(t.shape);
  if (n < 0) r.fail_at(key + ".tensorShape", "a constant needs a fully known shape");
  const std::size_t bytes = static_cast<std::size_t>(n) * dtype_size(t.dtype);
  if (const json* content = r.find(tensor, "tensorContent")) {
    const std::string raw =
        base64_decode(r.file(), key + ".tensorContent", r.string(*content, key));
    if (raw.size() != bytes) {
      r.fail_at(key + ".tensorContent", std::to_string(raw.size()) + " bytes for " +
                                            std::to_string(n) + " " +
                                            std::string(dtype_name(t.dtype)) + " values");
    }
    t.data.resize(bytes);
    std::memcpy(t.data.data(), raw.data(), bytes);
    return t;
  }
  // Typed value lists; fewer values than elements repeat the last (TensorProto semantics).
  const char* field = t.dtype == DType::kFloat32 ? "floatVal"
                      : t.dtype == DType::kBool  ? "boolVal"
                      : t.dtype == DType::kInt64 ? "int64Val"
                                                 : "intVal";
  const json* values = r.find(tensor, field);
  if (values == nullptr) return std::nullopt;
  const std::string vkey = key + "." + field;
  r.array(*values, vkey);
  if (values->empty() && n > 0) r.fail_at(vkey, "no values");
  if (static_cast<std::int64_t>(values->size()) > n) {
    r.fail_at(vkey,
              std::to_string(values->size()) + " values for " + std::to_string(n) + " elements");
  }
  t.data.reserve(bytes);
  for (std::int64_t k = 0; k < n; ++k) {
    const std::size_t src = std::min<std::size_t>(k, values->size() - 1);
    const json& v = (*values)[src];
    const std::string ekey = vkey + "[" + std::to_string(src) + "]";
    switch (t.dtype) {
      case DType::kFloat32:
        append_value(t.data, static_cast<float>(r.number(v, ekey)));
        break;
      case DType::kInt32:
        append_value(t.data, static_cast<std::int32_t>(r.int64(v, ekey)));
        break;
      case DType::kInt64:
        append_value(t.data, r.int64(v, ekey));
        break;
      case DType::kBool:
        append_value(t.data, static_cast<std::uint8_t>(r.boolean(v, ekey) ? 1 : 0));
        break;
    }
  }
  return t;
}

TensorRef parse_ref(std::string_view s, const std::unordered_map<std::string, int>& index,
                    bool* known) {
  TensorRef ref;
  std::string_view name = s;
  const std::size_t colon = s.rfind(':');
  if (colon != std::string_view::npos && colon + 1 < s.size() &&
      std::all_of(s.begin() + colon + 1, s.end(), [](char c) { return c >= '0' && c <= '9'; })) {
    name = s.substr(0, colon);
    ref.output = std::stoi(std::string(s.substr(colon + 1)));
  }
  auto it = index.find(std::string(name));
  *known = it != index.end();
  if (*known) ref.node = it->second;
  return ref;
}

struct RawNode {
  GraphNode node;
  std::vector<std::string> input_names;
};

// The manifest's weights, dequantized, keyed by name.
std::unordered_map<std::string, HostTensor> read_weights(const Reader& r, const json& manifest) {
  std::unordered_map<std::string, HostTensor> weights;
  const fs::path dir = r.file().parent_path();
  r.array(manifest, "weightsManifest");
  for (std::size_t g = 0; g < manifest.size(); ++g) {
    const std::string gkey = "weightsManifest[" + std::to_string(g) + "]";
    const json& group = manifest[g];
    const json& paths = r.array(r.need(group, "paths", gkey), gkey + ".paths");
    const json& entries = r.array(r.need(group, "weights", gkey), gkey + ".weights");
    std::string bytes;
    std::string shard_names;
    for (std::size_t p = 0; p < paths.size(); ++p) {
      const fs::path shard = dir / r.string(paths[p], gkey + ".paths[" + std::to_string(p) + "]");
      std::error_code ec;
      if (!fs::is_regular_file(shard, ec)) {
        fail(shard, "weight shard named by " + r.file().filename().string() + " is missing");
      }
      bytes += read_file(shard);
      shard_names += (shard_names.empty() ? "" : "+") + shard.string();
    }
    // First pass: sizes, so a truncated or wrong .bin is reported before anything is read.
    struct Entry {
      std::string name;
      DType dtype;
      std::vector<std::int64_t> shape;
      std::string quantized;  // "", "float16", "uint8", "uint16"
      double scale = 1, min = 0;
      std::size_t offset = 0, size = 0;
    };
    std::vector<Entry> parsed;
    std::size_t offset = 0;
    for (std::size_t w = 0; w < entries.size(); ++w) {
      const std::string wkey = gkey + ".weights[" + std::to_string(w) + "]";
      const json& e = entries[w];
      Entry entry;
      entry.name = r.string(r.need(e, "name", wkey), wkey + ".name");
      const std::string dt = r.string(r.need(e, "dtype", wkey), wkey + ".dtype");
      const std::optional<DType> d = dtype_from_manifest(dt);
      if (!d) {
        r.fail_at(wkey + ".dtype", "unknown dtype '" + dt + "' of weight '" + entry.name + "'");
      }
      entry.dtype = *d;
      const json& shape = r.array(r.need(e, "shape", wkey), wkey + ".shape");
      for (std::size_t k = 0; k < shape.size(); ++k) {
        const std::int64_t dim = r.int64(shape[k], wkey + ".shape[" + std::to_string(k) + "]");
        if (dim < 0) r.fail_at(wkey + ".shape", "negative dimension");
        entry.shape.push_back(dim);
      }
      std::size_t element_size = dtype_size(entry.dtype);
      if (const json* q = r.find(e, "quantization")) {
        const std::string qkey = wkey + ".quantization";
        entry.quantized = r.string(r.need(*q, "dtype", qkey), qkey + ".dtype");
        if (entry.dtype != DType::kFloat32) {
          r.fail_at(qkey, "quantized weight '" + entry.name + "' must be float32, is " + dt);
        }
        if (entry.quantized == "float16") {
          element_size = 2;
        } else if (entry.quantized == "uint8" || entry.quantized == "uint16") {
          element_size = entry.quantized == "uint8" ? 1 : 2;
          entry.scale = r.number(r.need(*q, "scale", qkey), qkey + ".scale");
          entry.min = r.number(r.need(*q, "min", qkey), qkey + ".min");
        } else {
          r.fail_at(qkey + ".dtype", "unknown quantization dtype '" + entry.quantized +
                                         "' of weight '" + entry.name + "'");
        }
      }
      entry.offset = offset;
      entry.size = static_cast<std::size_t>(element_count(entry.shape)) * element_size;
      offset += entry.size;
      parsed.push_back(std::move(entry));
    }
    if (offset != bytes.size()) {
      fail(shard_names.empty() ? r.file() : fs::path(shard_names),
           std::to_string(bytes.size()) + " bytes, but " + gkey + " of " +
               r.file().filename().string() + " needs " + std::to_string(offset) +
               (bytes.size() < offset ? " (truncated?)" : " (wrong file?)"));
    }
    for (Entry& entry : parsed) {
      HostTensor t;
      t.dtype = entry.dtype;
      t.shape = entry.shape;
      const std::int64_t n = element_count(entry.shape);
      const char* src = bytes.data() + entry.offset;
      if (entry.quantized.empty()) {
        t.data.resize(entry.size);
        std::memcpy(t.data.data(), src, entry.size);
      } else {
        std::vector<float> values(static_cast<std::size_t>(n));
        for (std::int64_t k = 0; k < n; ++k) {
          if (entry.quantized == "uint8") {
            values[k] =
                static_cast<float>(static_cast<std::uint8_t>(src[k]) * entry.scale + entry.min);
          } else {
            std::uint16_t bits;
            std::memcpy(&bits, src + 2 * k, 2);
            values[k] = entry.quantized == "float16"
                            ? half_to_float(bits)
                            : static_cast<float>(bits * entry.scale + entry.min);
          }
        }
        t.data.resize(values.size() * sizeof(float));
        std::memcpy(t.data.data(), values.data(), t.data.size());
      }
      // Random or damaged bytes show as non-finite floats; refused here rather than deep inside
      // the graph (a NaN heatmap, or an error from whatever op first meets them).
      if (t.dtype == DType::kFloat32) {
        for (std::size_t k = 0; k < t.data.size(); k += sizeof(float)) {
          float value;
          std::memcpy(&value, t.data.data() + k, sizeof value);
          if (!std::isfinite(value)) {
            fail(fs::path(shard_names),
                 "weight '" + entry.name + "' holds NaN or infinity (a damaged shard?)");
          }
        }
      }
      if (!weights.emplace(entry.name, std::move(t)).second) {
        r.fail_at(gkey, "weight '" + entry.name + "' appears twice");
      }
    }
  }
  return weights;
}

}  // namespace

std::string_view dtype_name(DType dtype) {
  switch (dtype) {
    case DType::kFloat32:
      return "float32";
    case DType::kInt32:
      return "int32";
    case DType::kInt64:
      return "int64";
    case DType::kBool:
      return "bool";
  }
  return "?";
}

std::size_t dtype_size(DType dtype) {
  switch (dtype) {
    case DType::kFloat32:
    case DType::kInt32:
      return 4;
    case DType::kInt64:
      return 8;
    case DType::kBool:
      return 1;
  }
  return 0;
}

std::int64_t HostTensor::numel() const { return element_count(shape); }

const AttrValue* GraphNode::attr(const std::string& key) const {
  auto it = attrs.find(key);
  return it == attrs.end() ? nullptr : &it->second;
}

int TfjsModel::find_node(std::string_view name) const {
  auto it = index.find(std::string(name));
  return it == index.end() ? -1 : it->second;
}

TensorRef TfjsModel::resolve(std::string_view tensor_name) const {
  bool known = false;
  const TensorRef ref = parse_ref(tensor_name, index, &known);
  if (!known) fail(topology_path, "no node named '" + std::string(tensor_name) + "'");
  return ref;
}

std::string TfjsModel::tensor_name(const TensorRef& ref) const {
  const std::string& name = nodes.at(ref.node).name;
  return ref.output == 0 ? name : name + ":" + std::to_string(ref.output);
}

std::string TfjsModel::where(int node) const {
  return topology_path.string() + ": node '" + nodes.at(node).name + "' (" + nodes.at(node).op +
         ")";
}

std::string TfjsModel::name() const {
  return base_model.empty() ? topology_path.stem().string() : base_model;
}

const std::vector<std::string>& supported_ops() {
  static const std::vector<std::string> ops = {
      // graph plumbing
      "Const", "Placeholder", "Identity", "StopGradient", "Snapshot", "NoOp",
      // convolutions and pooling
      "Conv2D", "_FusedConv2D", "DepthwiseConv2dNative", "FusedDepthwiseConv2dNative", "BiasAdd",
      "MaxPool", "ResizeBilinear",
      // element-wise
      "Cast", "Add", "AddV2", "AddN", "Sub", "Mul", "RealDiv", "FloorDiv", "Maximum", "Minimum",
      "SquaredDifference", "Abs", "Neg", "Exp", "Log", "Sqrt", "Rsqrt", "Square", "Reciprocal",
      "Floor", "Sigmoid", "Tanh", "Relu", "Relu6",
      // comparisons and logic
      "Equal", "NotEqual", "Less", "LessEqual", "Greater", "GreaterEqual", "LogicalAnd",
      "LogicalOr", "LogicalNot", "Select", "SelectV2",
      // reductions and selection
      "Sum", "Max", "Min", "Mean", "ArgMax", "TopKV2", "GatherNd",
      // shapes
      "Shape", "Size", "Reshape", "Squeeze", "ExpandDims", "StridedSlice", "Pack", "Unpack",
      "ConcatV2", "Split", "Tile", "Fill", "Range", "Transpose", "Pad"};
  return ops;
}

bool is_supported_op(std::string_view op) {
  static const std::set<std::string, std::less<>> ops(supported_ops().begin(),
                                                      supported_ops().end());
  return ops.contains(op);
}

float half_to_float(std::uint16_t bits) {
  const std::uint32_t sign = static_cast<std::uint32_t>(bits & 0x8000) << 16;
  const std::uint32_t exponent = (bits >> 10) & 0x1F;
  std::uint32_t mantissa = bits & 0x3FF;
  std::uint32_t out;
  if (exponent == 0) {
    if (mantissa == 0) {
      out = sign;
    } else {  // subnormal: renormalise
      int e = -1;
      do {
        ++e;
        mantissa <<= 1;
      } while ((mantissa & 0x400) == 0);
      out = sign | static_cast<std::uint32_t>(127 - 15 - e) << 23 | (mantissa & 0x3FF) << 13;
    }
  } else if (exponent == 0x1F) {
    out = sign | 0x7F800000u | mantissa << 13;
  } else {
    out = sign | (exponent + 127 - 15) << 23 | mantissa << 13;
  }
  return std::bit_cast<float>(out);
}

namespace {

// Node n of modelTopology.node as written (inputs still by name), its name added to `index`;
// its Const value from the weights (taken out of `weights`) or inline.
RawNode read_node(const Reader& r, const json& j, std::size_t n,
                  std::unordered_map<std::string, int>& index,
                  std::unordered_map<std::string, HostTensor>& weights) {
  const std::string nkey = "modelTopology.node[" + std::to_string(n) + "]";
  const fs::path& json_path = r.file();
  RawNode raw;
  GraphNode& node = raw.node;
  node.name = r.string(r.need(j, "name", nkey), nkey + ".name");
  const std::string where = "node '" + node.name + "'";
  node.op = r.string(r.need(j, "op", nkey), nkey + ".op");
  if (!is_supported_op(node.op)) {
    fail(json_path, where + ": unsupported op '" + node.op + "'");
  }
  if (!index.emplace(node.name, static_cast<int>(n)).second) {
    fail(json_path, where + ": the name appears twice");
  }
  if (const json* inputs = r.find(j, "input")) {
    r.array(*inputs, nkey + ".input");
    for (std::size_t k = 0; k < inputs->size(); ++k) {
      raw.input_names.push_back(r.string((*inputs)[k], nkey + ".input[" + std::to_string(k) + "]"));
    }
  }
  if (const json* attrs = r.find(j, "attr")) {
    if (!attrs->is_object()) r.fail_at(nkey + ".attr", "expected an object");
    for (const auto& [key, value] : attrs->items()) {
      try {
        node.attrs.emplace(key, parse_attr(r, value, key));
      } catch (const Error& e) {
        // Re-say it with the node's name: "<file>: node 'x': key 'attr.T.type': ...".
        const std::string prefix = json_path.string() + ": key '";
        std::string message = e.what();
        if (message.rfind(prefix, 0) == 0) message = message.substr(json_path.string().size() + 2);
        fail(json_path, where + ": attr " + message);
      }
    }
  }
  if (node.op != "Const") return raw;
  auto w = weights.find(node.name);
  if (w != weights.end()) {
    node.value = std::move(w->second);
    weights.erase(w);
    return raw;
  }
  const json* value = r.find(j, "attr");
  value = value ? r.find(*value, "value") : nullptr;
  const json* tensor = value ? r.find(*value, "tensor") : nullptr;
  if (tensor != nullptr) {
    try {
      node.value = read_inline_tensor(r, *tensor, "attr.value.tensor");
    } catch (const Error& e) {
      std::string message = e.what();
      message = message.substr(std::min(message.size(), json_path.string().size() + 2));
      fail(json_path, where + ": " + message);
    }
  }
  if (!node.value) {
    fail(json_path, where + ": Const has no value (neither in weightsManifest nor inline)");
  }
  return raw;
}

// Input names to (file-order) node references.
void resolve_inputs(std::vector<RawNode>& raw, const std::unordered_map<std::string, int>& index,
                    const fs::path& json_path) {
  for (RawNode& rn : raw) {
    for (const std::string& in : rn.input_names) {
      if (!in.empty() && in[0] == '^') {
        auto it = index.find(in.substr(1));
        if (it == index.end()) {
          fail(json_path, "node '" + rn.node.name + "': control input '" + in + "' names no node");
        }
        rn.node.control_inputs.push_back(it->second);
        continue;
      }
      bool known = false;
      const TensorRef ref = parse_ref(in, index, &known);
      if (!known) fail(json_path, "node '" + rn.node.name + "': input '" + in + "' names no node");
      rn.node.inputs.push_back(ref);
    }
  }
}

// Nodes in dependency order (depth-first, keeping file order where free); a cycle fails.
std::vector<int> topological_order(const std::vector<RawNode>& raw, const fs::path& json_path) {
  std::vector<int> order;
  order.reserve(raw.size());
  std::vector<int> state(raw.size(), 0);  // 0 new, 1 on the stack, 2 done
  for (std::size_t start = 0; start < raw.size(); ++start) {
    if (state[start] != 0) continue;
    // Iterative DFS: (node, next dependency to visit).
    std::vector<std::pair<int, std::size_t>> stack = {{static_cast<int>(start), 0}};
    state[start] = 1;
    while (!stack.empty()) {
      auto& [n, next] = stack.back();
      const GraphNode& node = raw[n].node;
      const std::size_t deps = node.inputs.size() + node.control_inputs.size();
      if (next < deps) {
        const int dep = next < node.inputs.size() ? node.inputs[next].node
                                                  : node.control_inputs[next - node.inputs.size()];
        ++next;
        if (state[dep] == 1) {
          fail(json_path, "node '" + node.name + "': the graph has a cycle through '" +
                              raw[dep].node.name + "'");
        }
        if (state[dep] == 0) {
          state[dep] = 1;
          stack.emplace_back(dep, 0);
        }
      } else {
        state[n] = 2;
        order.push_back(n);
        stack.pop_back();
      }
    }
  }
  return order;
}

// The raw nodes in `order`, their references renumbered, into model.nodes and model.index.
void place_nodes(std::vector<RawNode>& raw, const std::vector<int>& order, TfjsModel& model) {
  std::vector<int> position(raw.size());
  for (std::size_t k = 0; k < order.size(); ++k) position[order[k]] = static_cast<int>(k);
  model.nodes.reserve(raw.size());
  for (int n : order) {
    GraphNode node = std::move(raw[n].node);
    for (TensorRef& in : node.inputs) in.node = position[in.node];
    for (int& c : node.control_inputs) c = position[c];
    model.index.emplace(node.name, static_cast<int>(model.nodes.size()));
    model.nodes.push_back(std::move(node));
  }
}

// signature.inputs or signature.outputs, if the file has them.
std::vector<SignatureTensor> read_signature(const Reader& r, const json& doc, const char* section,
                                            const TfjsModel& model) {
  std::vector<SignatureTensor> out;
  const json* signature = r.find(doc, "signature");
  const json* entries = signature ? r.find(*signature, section) : nullptr;
  if (entries == nullptr) return out;
  const std::string skey = std::string("signature.") + section;
  if (!entries->is_object()) r.fail_at(skey, "expected an object");
  for (const auto& [key, value] : entries->items()) {
    const std::string ekey = skey + "." + key;
    SignatureTensor t;
    t.key = key;
    t.name = r.string(r.need(value, "name", ekey), ekey + ".name");
    bool known = false;
    t.ref = parse_ref(t.name, model.index, &known);
    if (!known) r.fail_at(ekey + ".name", "'" + t.name + "' names no node");
    if (const json* d = r.find(value, "dtype")) {
      const std::string dt = r.string(*d, ekey + ".dtype");
      t.dtype = dtype_from_tf(dt);
      if (!t.dtype) r.fail_at(ekey + ".dtype", "unknown dtype '" + dt + "'");
    }
    if (const json* s = r.find(value, "tensorShape")) t.shape = r.shape(*s, ekey + ".tensorShape");
    out.push_back(std::move(t));
  }
  return out;
}

// Without a declared signature: the Placeholders are the inputs.
std::vector<SignatureTensor> placeholder_inputs(const TfjsModel& model) {
  std::vector<SignatureTensor> inputs;
  for (std::size_t n = 0; n < model.nodes.size(); ++n) {
    const GraphNode& node = model.nodes[n];
    if (node.op != "Placeholder") continue;
    SignatureTensor t;
    t.key = node.name;
    t.name = node.name + ":0";
    t.ref = {static_cast<int>(n), 0};
    if (const AttrValue* d = node.attr("dtype"); d && d->kind == AttrValue::Kind::kType) {
      t.dtype = d->type;
    }
    if (const AttrValue* s = node.attr("shape"); s && s->kind == AttrValue::Kind::kShape) {
      t.shape = s->shape;
    }
    inputs.push_back(std::move(t));
  }
  return inputs;
}

// Without a declared signature: the nodes nothing consumes are the outputs.
std::vector<SignatureTensor> unconsumed_outputs(const TfjsModel& model) {
  std::vector<SignatureTensor> outputs;
  std::vector<bool> consumed(model.nodes.size(), false);
  for (const GraphNode& node : model.nodes) {
    for (const TensorRef& in : node.inputs) consumed[in.node] = true;
  }
  for (std::size_t n = 0; n < model.nodes.size(); ++n) {
    const std::string& op = model.nodes[n].op;
    if (consumed[n] || op == "Const" || op == "Placeholder" || op == "NoOp") continue;
    SignatureTensor t;
    t.key = model.nodes[n].name;
    t.name = model.nodes[n].name + ":0";
    t.ref = {static_cast<int>(n), 0};
    outputs.push_back(std::move(t));
  }
  return outputs;
}

}  // namespace

TfjsModel load_tfjs_model(const fs::path& json_path) {
  std::error_code ec;
  if (!fs::is_regular_file(json_path, ec)) fail(json_path, "no such model file");
  const Reader r(json_path);
  json doc;
  try {
    doc = json::parse(read_file(json_path));
  } catch (const json::parse_error& e) {
    fail(json_path, std::string("corrupt or truncated JSON (") + e.what() + ")");
  }
  if (!doc.is_object()) fail(json_path, "expected a JSON object (a TF.js model.json)");

  TfjsModel model;
  model.topology_path = json_path;
  if (const json* f = r.find(doc, "format")) model.format = r.string(*f, "format");
  if (!model.format.empty() && model.format != "graph-model") {
    r.fail_at("format", "'" + model.format + "' is not a TF.js graph model");
  }
  if (const json* g = r.find(doc, "generatedBy")) {
    model.generated_by = g->is_string() ? g->get<std::string>() : g->dump();
  }
  if (const json* meta = r.find(doc, "userDefinedMetadata"); meta && meta->is_object()) {
    if (const json* ours = r.find(*meta, "wheelpose"); ours && ours->is_object()) {
      if (const json* base = r.find(*ours, "base_model")) {
        model.base_model = r.string(*base, "userDefinedMetadata.wheelpose.base_model");
      }
    }
  }
  const json& topology = r.need(doc, "modelTopology", "modelTopology");
  const json& node_list = r.array(r.need(topology, "node", "modelTopology"), "modelTopology.node");
  std::unordered_map<std::string, HostTensor> weights =
      read_weights(r, r.need(doc, "weightsManifest", "weightsManifest"));

  std::vector<RawNode> raw;
  raw.reserve(node_list.size());
  std::unordered_map<std::string, int> file_index;
  for (std::size_t n = 0; n < node_list.size(); ++n) {
    raw.push_back(read_node(r, node_list[n], n, file_index, weights));
  }
  resolve_inputs(raw, file_index, json_path);
  place_nodes(raw, topological_order(raw, json_path), model);

  model.inputs = read_signature(r, doc, "inputs", model);
  model.outputs = read_signature(r, doc, "outputs", model);
  if (model.inputs.empty()) model.inputs = placeholder_inputs(model);
  for (const SignatureTensor& t : model.inputs) {
    if (model.nodes[t.ref.node].op != "Placeholder") {
      r.fail_at("signature.inputs." + t.key, "'" + t.name + "' is not a Placeholder");
    }
  }
  if (model.outputs.empty()) model.outputs = unconsumed_outputs(model);
  if (model.outputs.empty()) fail(json_path, "the graph has no outputs");
  return model;
}

}  // namespace wheelpose::learn
