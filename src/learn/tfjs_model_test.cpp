#include "learn/tfjs_model.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>

#include "core/atomic_file.h"
#include "core/error.h"
#include "learn/learn_test_support.h"

namespace wheelpose::learn {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;
using namespace wheelpose::learn::testing;  // NOLINT

const char kLightning[] = "movenet-lightning";
const char kConv1[] =
    "StatefulPartitionedCall/center_net_mobile_net_v2fpn_feature_extractor/model_1/model/Conv1/"
    "Conv2D_weights";

std::vector<float> floats_of(const HostTensor& t) {
  std::vector<float> v(static_cast<std::size_t>(t.numel()));
  std::memcpy(v.data(), t.data.data(), v.size() * sizeof(float));
  return v;
}
std::vector<std::int32_t> ints_of(const HostTensor& t) {
  std::vector<std::int32_t> v(static_cast<std::size_t>(t.numel()));
  std::memcpy(v.data(), t.data.data(), v.size() * sizeof(std::int32_t));
  return v;
}

TEST(HalfToFloat, DecodesNormalsSubnormalsAndSpecials) {
  EXPECT_EQ(half_to_float(0x3C00), 1.0f);
  EXPECT_EQ(half_to_float(0xC000), -2.0f);
  EXPECT_EQ(half_to_float(0x3555), 0.333251953125f);
  EXPECT_EQ(half_to_float(0x7BFF), 65504.0f);
  EXPECT_EQ(half_to_float(0x0400), std::ldexp(1.0f, -14));  // smallest normal
  EXPECT_EQ(half_to_float(0x0001), std::ldexp(1.0f, -24));  // smallest subnormal
  EXPECT_EQ(half_to_float(0x03FF), std::ldexp(1023.0f, -24));
  EXPECT_EQ(half_to_float(0x8000), -0.0f);
  EXPECT_TRUE(std::signbit(half_to_float(0x8000)));
  EXPECT_EQ(half_to_float(0x7C00), std::numeric_limits<float>::infinity());
  EXPECT_TRUE(std::isnan(half_to_float(0x7E00)));
}

TEST(TfjsModel, LoadsLightningGraphAndWeights) {
  WHEELPOSE_REQUIRE_MODEL(kLightning);
  const TfjsModel m = load_tfjs_model(model_json(kLightning));
  EXPECT_EQ(m.name(), kLightning);
  EXPECT_EQ(m.format, "graph-model");
  ASSERT_EQ(m.nodes.size(), 331u);
  std::map<std::string, int> ops;
  for (const GraphNode& n : m.nodes) ++ops[n.op];
  EXPECT_EQ(ops["Const"], 180);
  EXPECT_EQ(ops["_FusedConv2D"], 50);
  EXPECT_EQ(ops["FusedDepthwiseConv2dNative"], 17);
  // Topological: every input precedes its consumer.
  for (std::size_t n = 0; n < m.nodes.size(); ++n) {
    for (const TensorRef& in : m.nodes[n].inputs) EXPECT_LT(in.node, static_cast<int>(n));
  }
  ASSERT_EQ(m.inputs.size(), 1u);
  EXPECT_EQ(m.inputs[0].name, "input:0");
  EXPECT_EQ(m.nodes[m.inputs[0].ref.node].op, "Placeholder");
  EXPECT_EQ(m.inputs[0].dtype, DType::kInt32);
  ASSERT_EQ(m.outputs.size(), 1u);
  EXPECT_EQ(m.outputs[0].name, "Identity:0");
  EXPECT_EQ(m.outputs[0].shape, (std::vector<std::int64_t>{1, 1, 17, 3}));

  // float16-quantized weights, dequantized (values from the .bin read with Python's struct).
  const GraphNode& conv1 = m.nodes[m.find_node(kConv1)];
  ASSERT_TRUE(conv1.value);
  EXPECT_EQ(conv1.value->dtype, DType::kFloat32);
  EXPECT_EQ(conv1.value->shape, (std::vector<std::int64_t>{3, 3, 3, 32}));
  const std::vector<float> w = floats_of(*conv1.value);
  EXPECT_EQ(w[0], -0.458984375f);
  EXPECT_EQ(w[1], -2.951171875f);
  EXPECT_EQ(w[2], -0.91259765625f);
  EXPECT_EQ(w[4], 0.06427001953125f);
  // int32 weights as is.
  const GraphNode& shape = m.nodes[m.find_node("StatefulPartitionedCall/Reshape_11/shape")];
  ASSERT_TRUE(shape.value);
  EXPECT_EQ(shape.value->dtype, DType::kInt32);
  EXPECT_EQ(ints_of(*shape.value), (std::vector<std::int32_t>{17, 17, -1}));

  // Attributes: strings are base64-decoded, ints parsed from strings.
  const GraphNode* fused = nullptr;
  for (const GraphNode& n : m.nodes) {
    if (n.op == "_FusedConv2D" && n.inputs[1].node == m.find_node(kConv1)) fused = &n;
  }
  ASSERT_NE(fused, nullptr);
  EXPECT_EQ(fused->attr("padding")->s, "SAME");
  EXPECT_EQ(fused->attr("data_format")->s, "NHWC");
  EXPECT_EQ(fused->attr("strides")->ints, (std::vector<std::int64_t>{1, 2, 2, 1}));
  EXPECT_EQ(fused->attr("fused_ops")->strings, (std::vector<std::string>{"BiasAdd", "Relu6"}));
  EXPECT_EQ(fused->attr("num_args")->i, 1);

  EXPECT_EQ(m.tensor_name(m.resolve("Identity")), "Identity");
  EXPECT_THAT(error_of([&] { m.resolve("no/such/node:1"); }),
              AllOf(HasSubstr("movenet-lightning.json"), HasSubstr("no/such/node:1")));
}

TEST(TfjsModel, ReadsInlineConstantsAndFindsOutputsWithoutSignature) {
  TempDir dir("inline");
  json doc = GraphBuilder()
                 .placeholder("x", "DT_FLOAT", {2})
                 .const_float("c", {2}, {1.5f, -2.0f})
                 .const_int("splat", {2, 2}, {7})  // fewer values than elements: repeated
                 .node("sum", "AddV2", {"x", "c"}, {{"T", attr_type("DT_FLOAT")}})
                 .document();
  // A tensorContent constant (raw little-endian bytes, base64).
  const std::int32_t raw[3] = {3, -4, 5};
  doc["modelTopology"]["node"].push_back(
      {{"name", "content"},
       {"op", "Const"},
       {"attr",
        {{"value",
          {{"tensor",
            {{"dtype", "DT_INT32"},
             {"tensorShape", tensor_shape({3})},
             {"tensorContent", base64(std::string(reinterpret_cast<const char*>(raw), 12))}}}}}}}});
  const fs::path file = dir.path() / "inline.json";
  std::ofstream(file) << doc.dump();
  const TfjsModel m = load_tfjs_model(file);
  EXPECT_EQ(floats_of(*m.nodes[m.find_node("c")].value), (std::vector<float>{1.5f, -2.0f}));
  EXPECT_EQ(ints_of(*m.nodes[m.find_node("splat")].value), (std::vector<std::int32_t>{7, 7, 7, 7}));
  EXPECT_EQ(ints_of(*m.nodes[m.find_node("content")].value), (std::vector<std::int32_t>{3, -4, 5}));
  ASSERT_EQ(m.outputs.size(), 1u);  // the unconsumed non-constant node
  EXPECT_EQ(m.outputs[0].name, "sum:0");
  ASSERT_EQ(m.inputs.size(), 1u);
  EXPECT_EQ(m.inputs[0].name, "x:0");
}

TEST(TfjsModel, SortsNodesListedOutOfOrderAndRejectsCycles) {
  TempDir dir("order");
  GraphBuilder g;
  g.node("b", "Neg", {"a"}).placeholder("x", "DT_FLOAT", {1}).node("a", "Abs", {"x"});
  const TfjsModel m = load_tfjs_model(g.write(dir.path() / "order.json"));
  EXPECT_LT(m.find_node("x"), m.find_node("a"));
  EXPECT_LT(m.find_node("a"), m.find_node("b"));

  GraphBuilder cyclic;
  cyclic.placeholder("x", "DT_FLOAT", {1}).node("a", "AddV2", {"x", "b"}).node("b", "Neg", {"a"});
  const fs::path file = cyclic.write(dir.path() / "cycle.json");
  EXPECT_THAT(error_of([&] { load_tfjs_model(file); }),
              AllOf(HasSubstr("cycle.json"), HasSubstr("cycle")));

  GraphBuilder dangling;
  dangling.placeholder("x", "DT_FLOAT", {1}).node("a", "Abs", {"y:0"});
  const fs::path file2 = dangling.write(dir.path() / "dangling.json");
  EXPECT_THAT(error_of([&] { load_tfjs_model(file2); }),
              AllOf(HasSubstr("dangling.json"), HasSubstr("node 'a'"), HasSubstr("'y:0'")));
}

// A copy of lightning in a temp dir, to corrupt.
class CorruptModel : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!have_model(kLightning)) {
      GTEST_SKIP() << "model " << kLightning << " not found in " << models_dir()
                   << "; run scripts/setup.sh (or set WHEELPOSE_MODELS)";
    }
    json_ = dir_.path() / "movenet-lightning.json";
    bin_ = dir_.path() / "movenet-lightning.bin";
    fs::copy_file(model_json(kLightning), json_);
    fs::copy_file(models_dir() / "movenet-lightning.bin", bin_);
    doc_ = json::parse(read_file(json_));
  }
  void write_json(const json& doc) { std::ofstream(json_, std::ios::trunc) << doc.dump(); }
  std::string load_error() {
    return error_of([&] { load_tfjs_model(json_); });
  }

  TempDir dir_{"corrupt"};
  fs::path json_, bin_;
  json doc_;
};

TEST_F(CorruptModel, TruncatedBinNamesTheShardAndByteCounts) {
  fs::resize_file(bin_, fs::file_size(bin_) - 100);
  const std::string e = load_error();
  EXPECT_THAT(e, AllOf(HasSubstr(bin_.string()), HasSubstr("4650116 bytes"),
                       HasSubstr("needs 4650216"), HasSubstr("truncated")));
  EXPECT_EQ(e.find('\n'), std::string::npos) << e;
}

TEST_F(CorruptModel, LongerBinIsRefusedToo) {
  std::ofstream(bin_, std::ios::app | std::ios::binary) << "extra";
  EXPECT_THAT(load_error(), AllOf(HasSubstr(bin_.string()), HasSubstr("4650221 bytes")));
}

TEST_F(CorruptModel, MissingBinIsNamed) {
  fs::remove(bin_);
  EXPECT_THAT(load_error(), AllOf(HasSubstr(bin_.string()), HasSubstr("missing")));
}

TEST_F(CorruptModel, MissingModelTopology) {
  doc_.erase("modelTopology");
  write_json(doc_);
  EXPECT_THAT(load_error(), AllOf(HasSubstr(json_.string()), HasSubstr("modelTopology")));
}

TEST_F(CorruptModel, TruncatedJson) {
  const std::string text = read_file(json_);
  std::ofstream(json_, std::ios::trunc) << text.substr(0, text.size() / 2);
  EXPECT_THAT(load_error(), AllOf(HasSubstr(json_.string()), HasSubstr("corrupt or truncated")));
}

TEST_F(CorruptModel, UnknownOpNamesOpAndNode) {
  for (json& node : doc_["modelTopology"]["node"]) {
    if (node["name"] == "StatefulPartitionedCall/Sigmoid") node["op"] = "FancyOp";
  }
  write_json(doc_);
  EXPECT_THAT(load_error(), AllOf(HasSubstr(json_.string()), HasSubstr("'FancyOp'"),
                                  HasSubstr("node 'StatefulPartitionedCall/Sigmoid'")));
}

TEST_F(CorruptModel, UnknownDtypes) {
  doc_["weightsManifest"][0]["weights"][0]["dtype"] = "complex64";
  write_json(doc_);
  EXPECT_THAT(load_error(), AllOf(HasSubstr(json_.string()), HasSubstr("complex64"),
                                  HasSubstr("weightsManifest[0].weights[0].dtype")));

  doc_ = json::parse(read_file(model_json(kLightning)));
  doc_["weightsManifest"][0]["weights"][1]["quantization"]["dtype"] = "int4";
  write_json(doc_);
  EXPECT_THAT(load_error(), AllOf(HasSubstr("int4"), HasSubstr("quantization")));

  doc_ = json::parse(read_file(model_json(kLightning)));
  for (json& node : doc_["modelTopology"]["node"]) {
    if (node["name"] == "StatefulPartitionedCall/Sigmoid")
      node["attr"]["T"]["type"] = "DT_COMPLEX64";
  }
  write_json(doc_);
  EXPECT_THAT(load_error(), AllOf(HasSubstr("DT_COMPLEX64"),
                                  HasSubstr("node 'StatefulPartitionedCall/Sigmoid'")));
}

TEST_F(CorruptModel, ConstWithoutValue) {
  auto& weights = doc_["weightsManifest"][0]["weights"];
  // Drop the last weight from the manifest and its bytes from the .bin: its Const node is left
  // without a value.
  const json last = weights.back();
  weights.erase(weights.size() - 1);
  std::size_t n = last.contains("quantization") ? 2 : 4;  // float16 or int32
  for (const json& d : last["shape"]) n *= d.get<std::size_t>();
  fs::resize_file(bin_, fs::file_size(bin_) - n);
  write_json(doc_);
  EXPECT_THAT(load_error(), AllOf(HasSubstr("node '" + last["name"].get<std::string>() + "'"),
                                  HasSubstr("has no value")));
}

}  // namespace
}  // namespace wheelpose::learn
