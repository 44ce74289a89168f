#pragma once
// A TF.js graph model (model.json + .bin weight shards, as written by tensorflowjs_converter)
// read into a plain graph description: nodes in topological order with their parsed attributes
// and the constant values (float16/uint8/uint16-quantized weights dequantized to float32).
// Torch-free, so any layer may include it; learn/graph_module.h executes the graph.
//
// Every rejection is one line naming the file and the node or JSON key: corrupt or truncated
// JSON, a .bin whose byte count differs from the manifest, an unknown dtype or quantization,
// an input that names no node, a cycle, and any op outside supported_ops() (detected here, at
// load time, never skipped at run time).

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace wheelpose::learn {

enum class DType { kFloat32, kInt32, kInt64, kBool };

// "float32", "int32", "int64", "bool".
std::string_view dtype_name(DType dtype);
// Bytes per element in HostTensor::data.
std::size_t dtype_size(DType dtype);

// A constant's value, row-major, in the dtype's native layout (bool: one byte per element).
struct HostTensor {
  DType dtype = DType::kFloat32;
  std::vector<std::int64_t> shape;
  std::vector<std::byte> data;
  std::int64_t numel() const;
};

// One entry of a node's `attr` map (a TensorFlow AttrValue in its JSON form).
struct AttrValue {
  enum class Kind { kInt, kFloat, kBool, kString, kType, kShape, kTensor, kList };
  Kind kind = Kind::kInt;
  std::int64_t i = 0;
  double f = 0;
  bool b = false;
  std::string s;                     // kString, base64-decoded
  DType type = DType::kFloat32;      // kType (DT_STRING etc. map to nothing: kept as s)
  std::vector<std::int64_t> shape;   // kShape: dims, -1 when unknown
  std::vector<std::int64_t> ints;    // kList
  std::vector<double> floats;        // kList
  std::vector<std::string> strings;  // kList, base64-decoded
};

// The `k`-th output of node `node` (an index into TfjsModel::nodes).
struct TensorRef {
  int node = -1;
  int output = 0;
  bool operator==(const TensorRef&) const = default;
};

struct GraphNode {
  std::string name;
  std::string op;
  std::vector<TensorRef> inputs;    // data inputs, in order
  std::vector<int> control_inputs;  // "^name" inputs: ordering only
  std::map<std::string, AttrValue> attrs;
  std::optional<HostTensor> value;  // Const nodes: from the manifest or inline

  const AttrValue* attr(const std::string& key) const;
};

// An entry of the model's `signature` inputs or outputs.
struct SignatureTensor {
  std::string key;   // e.g. "input", "output_0"
  std::string name;  // tensor name, e.g. "input:0", "Identity:0"
  TensorRef ref;
  std::optional<DType> dtype;
  std::vector<std::int64_t> shape;  // -1 when unknown; empty when not given
};

struct TfjsModel {
  std::filesystem::path topology_path;  // the .json
  std::string format;                   // "graph-model"
  std::string generated_by;
  // userDefinedMetadata.wheelpose.base_model of a model `wheelpose model export` wrote: the
  // MoveNet model whose topology it shares, so weights trained from it stay loadable by name.
  std::string base_model;
  std::vector<GraphNode> nodes;          // topological order: every input precedes its consumer
  std::vector<SignatureTensor> inputs;   // the Placeholders
  std::vector<SignatureTensor> outputs;  // signature outputs, else the unconsumed nodes

  // Index of node `name` in `nodes`, -1 if none.
  int find_node(std::string_view name) const;
  // "name" or "name:k" to a TensorRef; throws Error naming the file when unknown.
  TensorRef resolve(std::string_view tensor_name) const;
  // "name" for output 0, else "name:k".
  std::string tensor_name(const TensorRef& ref) const;
  // "<file>: node '<name>' (<op>)", the prefix of errors about a node.
  std::string where(int node) const;
  // The model's name: base_model when set, else the topology file's stem, e.g.
  // "movenet-lightning". Weights files (.pt) record it; they load into any model of that name.
  std::string name() const;

  std::unordered_map<std::string, int> index;  // node name -> position in `nodes`
};

// The ops the executor (learn/graph_module.h) implements.
const std::vector<std::string>& supported_ops();
bool is_supported_op(std::string_view op);

// Reads `json_path` and the weight shards its manifest names (relative to its folder).
TfjsModel load_tfjs_model(const std::filesystem::path& json_path);

// IEEE 754 binary16 bits to float (exact; subnormals, inf and NaN included).
float half_to_float(std::uint16_t bits);

}  // namespace wheelpose::learn
