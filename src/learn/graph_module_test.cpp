#include "learn/graph_module.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/allocator.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "learn/learn_test_support.h"
#include "learn/weights_file.h"

namespace wheelpose::learn {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;
using namespace wheelpose::learn::testing;  // NOLINT
using torch::Tensor;

const char kMultipose[] = "movenet-multipose";
const char kLightning[] = "movenet-lightning";
const char kThunder[] = "movenet-thunder";

std::vector<float> values(const Tensor& t) {
  const Tensor c = t.detach().to(torch::kFloat).contiguous();
  return std::vector<float>(c.data_ptr<float>(), c.data_ptr<float>() + c.numel());
}

Tensor zeros_input(std::int64_t h, std::int64_t w) {
  return torch::zeros({1, h, w, 3}, torch::kInt);
}

// The graph node of the first convolution's filter.
std::string first_conv_filter(const GraphModule& m) {
  for (const GraphNode& n : m.graph().nodes) {
    if (n.op == "_FusedConv2D" || n.op == "Conv2D") return m.graph().nodes[n.inputs[1].node].name;
  }
  return "";
}

// The keypoint heatmap head before its sigmoid.
std::string heatmap_logits(const GraphModule& m) {
  for (const GraphNode& n : m.graph().nodes) {
    if (n.op != "Sigmoid") continue;
    const std::string& in = m.graph().nodes[n.inputs[0].node].name;
    if (in.find("kpt_heatmap") != std::string::npos) return in;
  }
  return "";
}

TEST(GraphModule, FusedConvFromConstantsIsTrainableAndPadsLikeTf) {
  TempDir dir("fused");
  GraphBuilder g;
  g.placeholder("x", "DT_FLOAT", {1, -1, -1, 1})
      .const_float("w", {3, 3, 1, 1}, std::vector<float>(9, 1.0f))
      .const_float("b", {1}, {0.5f})
      .node("conv", "_FusedConv2D", {"x", "w", "b"},
            {{"T", attr_type("DT_FLOAT")},
             {"strides", attr_ints({1, 2, 2, 1})},
             {"padding", attr_s("SAME")},
             {"data_format", attr_s("NHWC")},
             {"fused_ops", attr_strings({"BiasAdd"})},
             {"num_args", attr_i(1)},
             {"explicit_paddings", {{"list", json::object()}}}})
      .output("conv");
  GraphModule m(g.write(dir.path() / "fused.json"));
  EXPECT_EQ(m.parameter_nodes(), (std::vector<std::string>{"w", "b"}));
  EXPECT_EQ(m.parameter("w").sizes().vec(), (std::vector<std::int64_t>{1, 1, 3, 3}));  // torch
  EXPECT_TRUE(m.parameter("w").requires_grad());
  const Tensor x = torch::arange(1, 17, torch::kFloat).reshape({1, 4, 4, 1});
  const TensorMap out = m.forward(x);
  ASSERT_EQ(out.count("conv"), 1u);
  EXPECT_EQ(values(out.at("conv")), (std::vector<float>{54.5f, 45.5f, 72.5f, 54.5f}));
  // d(sum)/dw[a][b] = sum of the inputs each tap sees; the (0, 0) tap sees 1 + 3 + 9 + 11.
  out.at("conv").sum().backward();
  const Tensor grad = m.parameter("w").grad();
  ASSERT_TRUE(grad.defined());
  EXPECT_EQ(values(grad)[0], 24.0f);
  EXPECT_EQ(values(m.parameter("b").grad())[0], 4.0f);
}

TEST(GraphModule, ShapeOpsFollowTheInputSize) {
  // size = Shape(x)[1:3] * 2; y = ResizeBilinear(x, size), half-pixel centres.
  TempDir dir("shape");
  GraphBuilder g;
  g.placeholder("x", "DT_FLOAT", {1, -1, -1, 2})
      .node("shape", "Shape", {"x"}, {{"out_type", attr_type("DT_INT32")}})
      .const_int("begin", {1}, {1})
      .const_int("end", {1}, {3})
      .const_int("stride", {1}, {1})
      .node("hw", "StridedSlice", {"shape", "begin", "end", "stride"},
            {{"begin_mask", attr_i(0)}, {"end_mask", attr_i(0)}})
      .const_int("two", {}, {2})
      .node("size", "Mul", {"hw", "two"})
      .node("up", "ResizeBilinear", {"x", "size"},
            {{"align_corners", attr_b(false)}, {"half_pixel_centers", attr_b(true)}})
      .output("up");
  GraphModule m(g.write(dir.path() / "shape.json"));
  for (const auto& [h, w] : std::vector<std::pair<int, int>>{{3, 5}, {8, 2}}) {
    const TensorMap out = m.forward(torch::rand({1, h, w, 2}), {"size", "shape"});
    EXPECT_EQ(out.at("up").sizes().vec(), (std::vector<std::int64_t>{1, 2 * h, 2 * w, 2}));
    EXPECT_EQ(out.at("size").scalar_type(), torch::kInt);
    EXPECT_EQ(values(out.at("shape")), (std::vector<float>{1, float(h), float(w), 2}));
  }
  EXPECT_THAT(error_of([&] { m.set_capture({"nope"}); }),
              AllOf(HasSubstr("shape.json"), HasSubstr("'nope'")));
  EXPECT_THAT(error_of([&] {
                m.forward(torch::rand({1, 3, 3, 3}));
              }),
              AllOf(HasSubstr("shape.json"), HasSubstr("1×?×?×2")));
}

TEST(GraphModule, RunTimeErrorsNameTheNode) {
  TempDir dir("runtime");
  GraphBuilder g;
  g.placeholder("x", "DT_FLOAT", {-1})
      .const_int("shape", {2}, {3, 5})
      .node("bad_reshape", "Reshape", {"x", "shape"})
      .output("bad_reshape");
  GraphModule m(g.write(dir.path() / "runtime.json"));
  EXPECT_THAT(error_of([&] { m.forward(torch::zeros({7})); }),
              AllOf(HasSubstr("runtime.json"), HasSubstr("node 'bad_reshape' (Reshape)")));
}

TEST(GraphModule, RejectsUnsupportedAttributesAtConstruction) {
  TempDir dir("attrs");
  GraphBuilder g;
  g.placeholder("x", "DT_FLOAT", {1, 4, 4, 1})
      .const_float("w", {1, 1, 1, 1}, {1})
      .const_float("b", {1}, {0})
      .node("conv", "_FusedConv2D", {"x", "w", "b"},
            {{"strides", attr_ints({1, 1, 1, 1})},
             {"padding", attr_s("SAME")},
             {"fused_ops", attr_strings({"BiasAdd", "Gelu"})},
             {"num_args", attr_i(1)}})
      .output("conv");
  EXPECT_THAT(error_of([&] { GraphModule m(g.write(dir.path() / "attrs.json")); }),
              AllOf(HasSubstr("attrs.json"), HasSubstr("node 'conv'"), HasSubstr("Gelu")));
}

TEST(GraphModule, EverySupportedOpHasAKernel) {
  // The loader accepts supported_ops(); the executor must implement each of them. A node with
  // the wrong inputs or attributes may be refused, but never as an unsupported op.
  TempDir dir("kernels");
  for (const std::string& op : supported_ops()) {
    if (op == "Placeholder") continue;
    GraphBuilder g;
    g.placeholder("x", "DT_FLOAT", {1, 2, 2, 1}).node("y", op, {"x"}).output("x");
    const fs::path file = g.write(dir.path() / "kernel.json");
    const std::string e = error_of([&] { GraphModule m(file); });
    EXPECT_EQ(e.find("unsupported op"), std::string::npos) << op << ": " << e;
  }
}

class Models : public ::testing::Test {
 protected:
  void SetUp() override { torch::set_num_threads(2); }
};

TEST_F(Models, AllThreeRunAndGiveTheirOutputShapes) {
  struct Case {
    const char* model;
    std::int64_t h, w;
    std::vector<std::int64_t> shape;
  };
  for (const Case& c : std::vector<Case>{{kMultipose, 256, 256, {1, 6, 56}},
                                         {kMultipose, 320, 480, {1, 6, 56}},
                                         {kLightning, 192, 192, {1, 1, 17, 3}},
                                         {kThunder, 256, 256, {1, 1, 17, 3}}}) {
    if (!have_model(c.model)) {
      GTEST_SKIP() << "model " << c.model << " not found in " << models_dir()
                   << "; run scripts/setup.sh (or set WHEELPOSE_MODELS)";
    }
    GraphModule m(model_json(c.model));
    EXPECT_EQ(m.output_names(), (std::vector<std::string>{"Identity:0"}));
    torch::NoGradGuard no_grad;
    const Tensor y = m.forward(zeros_input(c.h, c.w)).at("Identity:0");
    EXPECT_EQ(y.sizes().vec(), c.shape) << c.model << " " << c.h << "x" << c.w;
    EXPECT_EQ(y.scalar_type(), torch::kFloat);
    EXPECT_TRUE(torch::isfinite(y).all().item<bool>()) << c.model;
    if (c.shape.size() == 4) {
      // A blank image: (y, x) inside the image, low scores.
      const Tensor scores = y.select(-1, 2);
      EXPECT_LT(scores.max().item<float>(), 0.35f) << c.model;
      EXPECT_GE(y.min().item<float>(), 0.0f);
      EXPECT_LE(y.max().item<float>(), 1.0f);
    } else {
      EXPECT_LT(y.select(-1, 55).max().item<float>(), 0.2f) << "person scores on a blank image";
    }
  }
}

TEST_F(Models, WrongInputSizeIsRefused) {
  WHEELPOSE_REQUIRE_MODEL(kLightning);
  GraphModule m(model_json(kLightning));
  torch::NoGradGuard no_grad;
  EXPECT_THAT(error_of([&] { m.forward(zeros_input(256, 256)); }),
              AllOf(HasSubstr("movenet-lightning.json"), HasSubstr("1×192×192×3"),
                    HasSubstr("1×256×256×3")));
}

TEST_F(Models, ChannelsLastAndNchwAgree) {
  WHEELPOSE_REQUIRE_MODEL(kMultipose);
  GraphModule m(model_json(kMultipose));
  torch::manual_seed(1);
  const Tensor x = torch::randint(0, 256, {1, 256, 320, 3}, torch::kInt);
  torch::InferenceMode guard;
  const std::string head = heatmap_logits(m);
  const TensorMap a = m.forward(x, {head});
  m.set_channels_last(false);
  const TensorMap b = m.forward(x, {head});
  EXPECT_LT((a.at(head) - b.at(head)).abs().max().item<float>(), 2e-3f);
  EXPECT_LT((a.at("Identity:0") - b.at("Identity:0")).abs().max().item<float>(), 1e-3f);
}

TEST_F(Models, GradientsReachTheFirstConvolution) {
  for (const char* name : {kLightning, kMultipose}) {
    if (!have_model(name)) {
      GTEST_SKIP() << "model " << name << " not found; run scripts/setup.sh";
    }
    GraphModule m(model_json(name));
    const std::string head = heatmap_logits(m);
    ASSERT_FALSE(head.empty()) << name;
    const std::int64_t size = std::string(name) == kLightning ? 192 : 256;
    torch::manual_seed(2);
    const Tensor x = torch::randint(0, 256, {1, size, size, 3}, torch::kInt);
    m.forward(x, {head}).at(head).sum().backward();
    const Tensor grad = m.parameter(first_conv_filter(m)).grad();
    ASSERT_TRUE(grad.defined()) << name;
    EXPECT_GT(grad.abs().sum().item<float>(), 0.0f) << name;
    // Every parameter the heatmap depends on has a gradient; the other heads' do not.
    int with_grad = 0;
    for (const Tensor& p : m.parameters()) with_grad += p.grad().defined() ? 1 : 0;
    EXPECT_GT(with_grad, 100) << name;
  }
}

TEST_F(Models, FinalOutputIsDifferentiable) {
  WHEELPOSE_REQUIRE_MODEL(kLightning);
  GraphModule m(model_json(kLightning));
  torch::manual_seed(4);
  // A float input keeps the image differentiable too.
  const Tensor x = (torch::rand({1, 192, 192, 3}) * 255).requires_grad_();
  const Tensor y = m.forward(x).at("Identity:0");
  ASSERT_TRUE(y.requires_grad());
  y.sum().backward();  // scores and the offset-refined coordinates
  EXPECT_GT(m.parameter(first_conv_filter(m)).grad().abs().sum().item<float>(), 0.0f);
  EXPECT_GT(x.grad().abs().sum().item<float>(), 0.0f);
}

TEST_F(Models, SaveAndLoadFineTunedWeights) {
  WHEELPOSE_REQUIRE_MODEL(kLightning);
  TempDir dir("weights");
  const fs::path pt = dir.path() / "tuned.pt";
  const Tensor x = torch::randint(0, 256, {1, 192, 192, 3}, torch::kInt);
  GraphModule tuned(model_json(kLightning));
  {
    torch::NoGradGuard no_grad;
    tuned.parameter(first_conv_filter(tuned)).mul_(1.5);
  }
  tuned.save(pt);
  EXPECT_EQ(weights_model_name(pt), kLightning);

  GraphModule fresh(model_json(kLightning));
  torch::NoGradGuard no_grad;
  const Tensor want = tuned.forward(x).at("Identity:0");
  EXPECT_FALSE(torch::equal(fresh.forward(x).at("Identity:0"), want));
  fresh.load(pt);
  EXPECT_TRUE(torch::equal(fresh.forward(x).at("Identity:0"), want));

  // Another model's file (thunder has the same node names and shapes as lightning).
  if (have_model(kThunder)) {
    GraphModule thunder(model_json(kThunder));
    EXPECT_THAT(error_of([&] { thunder.load(pt); }),
                AllOf(HasSubstr(pt.string()), HasSubstr("'movenet-lightning'"),
                      HasSubstr("movenet-thunder.json")));
  }
  // Names or shapes that do not fit.
  c10::Dict<std::string, Tensor> params;
  for (const std::string& node : fresh.parameter_nodes()) {
    params.insert(node, fresh.parameter(node).detach());
  }
  params.insert_or_assign(first_conv_filter(fresh), torch::zeros({2, 2}));
  params.insert("extra/node", torch::zeros({1}));
  c10::impl::GenericDict dict(c10::StringType::get(), c10::AnyType::get());
  dict.insert(std::string("format"), std::string(kWeightsFormat));
  dict.insert(std::string("version"), static_cast<std::int64_t>(1));
  dict.insert(std::string("model"), std::string(kLightning));
  dict.insert(std::string("parameters"), params);
  const std::vector<char> bytes = torch::pickle_save(c10::IValue(dict));
  const fs::path bad = dir.path() / "bad.pt";
  write_file_atomic(bad, std::string_view(bytes.data(), bytes.size()));
  const std::string e = error_of([&] { fresh.load(bad); });
  EXPECT_THAT(e, AllOf(HasSubstr(bad.string()), HasSubstr("1 unknown (first 'extra/node')"),
                       HasSubstr("1 of another shape"), HasSubstr("Conv1/Conv2D_weights")));
  EXPECT_EQ(e.find('\n'), std::string::npos);
  // Not a weights file at all.
  const fs::path garbage = dir.path() / "garbage.pt";
  write_file_atomic(garbage, std::string_view("not a pickle"));
  EXPECT_THAT(error_of([&] { fresh.load(garbage); }),
              AllOf(HasSubstr(garbage.string()), HasSubstr("not a weights file")));
  EXPECT_THAT(error_of([&] { weights_model_name(garbage); }), HasSubstr(garbage.string()));
}

// The COCO sample's skier: single-person models put the keypoints on the person.
TEST_F(Models, SinglePersonKeypointsLandOnTheSkier) {
  const fs::path image = fs::path(WHEELPOSE_SHARED_DIR) / "data/coco-sample/000000000785.jpg";
  const fs::path labels =
      fs::path(WHEELPOSE_SHARED_DIR) / "data/coco-sample/person_keypoints_sample.json";
  if (!fs::exists(image)) GTEST_SKIP() << image << " missing (shared test data)";
  const json coco = json::parse(read_file(labels));
  std::vector<double> gt;
  for (const json& a : coco["annotations"]) {
    if (a["image_id"] == 785) gt = a["keypoints"].get<std::vector<double>>();
  }
  ASSERT_EQ(gt.size(), 51u);
  cv::Mat bgr = cv::imread(image.string(), cv::IMREAD_COLOR);
  ASSERT_FALSE(bgr.empty());
  cv::Mat rgb, square;
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  const int side = std::max(rgb.cols, rgb.rows);  // pad bottom/right to a square
  cv::copyMakeBorder(rgb, square, 0, side - rgb.rows, 0, side - rgb.cols, cv::BORDER_CONSTANT,
                     cv::Scalar::all(0));
  for (const auto& [name, size] :
       std::vector<std::pair<const char*, int>>{{kLightning, 192}, {kThunder, 256}}) {
    if (!have_model(name)) continue;
    cv::Mat input;
    cv::resize(square, input, cv::Size(size, size), 0, 0, cv::INTER_AREA);
    const Tensor x =
        torch::from_blob(input.data, {1, size, size, 3}, torch::kUInt8).to(torch::kInt).clone();
    GraphModule m(model_json(name));
    torch::InferenceMode guard;
    const Tensor y = m.forward(x).at("Identity:0").reshape({17, 3});
    const std::vector<float> v = values(y);
    double score_sum = 0;
    int close = 0;
    std::vector<double> errors;
    for (int k = 0; k < 17; ++k) {
      const double py = v[3 * k] * side, px = v[3 * k + 1] * side;
      const double err = std::hypot(px - gt[3 * k], py - gt[3 * k + 1]);
      errors.push_back(err);
      score_sum += v[3 * k + 2];
      close += err < 25 ? 1 : 0;  // px in the 640×425 image; the person is ~220×350
    }
    std::sort(errors.begin(), errors.end());
    std::printf("[ NOTE ] %s: mean score %.3f, median error %.1f px, %d/17 within 25 px\n", name,
                score_sum / 17, errors[8], close);
    EXPECT_GT(score_sum / 17, 0.4) << name;
    EXPECT_LT(errors[8], 12.0) << name;
    EXPECT_GE(close, 14) << name;
  }
}

// Forward timings (ms/image, batch 1, 2 threads) on an idle machine. Run with
// --gtest_also_run_disabled_tests --gtest_filter='*Timing*'.
TEST_F(Models, DISABLED_Timing) {
  // As `wheelpose predict` does (core/allocator.h).
  retain_freed_memory();
  retain_large_blocks();
  struct Case {
    const char* model;
    std::int64_t size;
  };
  for (const Case& c : std::vector<Case>{
           {kMultipose, 256}, {kMultipose, 512}, {kLightning, 192}, {kThunder, 256}}) {
    if (!have_model(c.model)) continue;
    GraphModule m(model_json(c.model));
    const Tensor x = torch::randint(0, 256, {1, c.size, c.size, 3}, torch::kInt);
    for (const bool channels_last : {true, false}) {
      m.set_channels_last(channels_last);
      for (const bool inference_mode : {false, true}) {
        auto run = [&] {
          if (inference_mode) {
            torch::InferenceMode guard;
            m.forward(x);
          } else {
            torch::NoGradGuard guard;
            m.forward(x);
          }
        };
        for (int i = 0; i < 3; ++i) run();
        std::vector<double> ms;
        for (int i = 0; i < 15; ++i) {
          const auto t0 = std::chrono::steady_clock::now();
          run();
          ms.push_back(
              std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                  .count());
        }
        std::sort(ms.begin(), ms.end());
        std::printf("[ TIME ] %-18s %4ld  %-13s %-14s median %7.2f ms  min %7.2f ms\n", c.model,
                    static_cast<long>(c.size), channels_last ? "channels-last" : "nchw",
                    inference_mode ? "InferenceMode" : "NoGradGuard", ms[ms.size() / 2], ms[0]);
      }
    }
  }
}

}  // namespace
}  // namespace wheelpose::learn
