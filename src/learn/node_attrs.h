#pragma once
// Reads one TF.js graph node's attributes and checks its input count; a missing or mistyped
// attribute is an Error naming the model file and the node. Internal to the learn layer.

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "learn/graph_ops.h"
#include "learn/tfjs_model.h"

namespace wheelpose::learn {

class NodeAttrs {
 public:
  NodeAttrs(const TfjsModel& model, int node) : model_(model), node_(node) {}
  [[noreturn]] void fail(const std::string& message) const;
  const GraphNode& node() const { return model_.nodes[node_]; }

  // The attribute, or nullptr if absent; present with another kind fails.
  const AttrValue* find(const std::string& key, AttrValue::Kind kind) const;
  // Typed reads; without a fallback a missing attribute fails.
  std::int64_t i(const std::string& key, std::optional<std::int64_t> fallback = {}) const;
  bool b(const std::string& key, bool fallback) const;
  double f(const std::string& key, double fallback) const;
  std::string s(const std::string& key, std::optional<std::string> fallback = {}) const;
  std::vector<std::int64_t> ints(const std::string& key,
                                 std::optional<std::vector<std::int64_t>> fallback = {}) const;
  std::vector<std::string> strings(const std::string& key) const;
  std::optional<DType> type(const std::string& key) const;

  // Fails unless the node has n (or min..max) inputs.
  void inputs(std::size_t n) const { inputs(n, n); }
  void inputs(std::size_t min, std::size_t max) const;
  // Fails unless data_format is NHWC (the default).
  void nhwc() const;
  // A 4-vector attr [1, h, w, 1] (strides, dilations, ksize) as {h, w}.
  std::array<std::int64_t, 2> hw(const std::string& key, std::int64_t fallback) const;
  // The padding attr (SAME, VALID or EXPLICIT with explicit_paddings).
  ops::Padding padding() const;

 private:
  const TfjsModel& model_;
  int node_;
};

}  // namespace wheelpose::learn
