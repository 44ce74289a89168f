#include "learn/model_export.h"

#include <gtest/gtest.h>
#include <torch/torch.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "core/atomic_file.h"
#include "learn/graph_module.h"
#include "learn/learn_test_support.h"
#include "learn/letterbox.h"

namespace wheelpose::learn {
namespace {

using testing::error_of;
using testing::json;
using testing::TempDir;
namespace fs = std::filesystem;

constexpr const char* kMultipose = "movenet-multipose";

// The pretrained weights, each parameter shifted by a small deterministic pattern: a stand-in
// for a fine-tuned .pt that still finds people.
fs::path write_shifted_weights(const fs::path& out) {
  GraphModule module(testing::model_json(kMultipose));
  torch::NoGradGuard no_grad;
  int k = 0;
  for (const std::string& node : module.parameter_nodes()) {
    torch::Tensor p = module.parameter(node);
    const torch::Tensor pattern = torch::sin(torch::arange(p.numel()).to(torch::kFloat) + k++);
    p.add_(pattern.reshape(p.sizes()) * p.abs().mean() * 0.005);
  }
  module.save(out);
  return out;
}

torch::Tensor run(GraphModule& module, const cv::Mat& rgb) {
  torch::InferenceMode guard;
  const torch::Tensor input =
      torch::from_blob(rgb.clone().data, {1, rgb.rows, rgb.cols, 3}, torch::kUInt8)
          .to(torch::kInt32);
  return module.forward(input).at("Identity:0").contiguous();
}

fs::path frame_file(int index) {
  return fs::path(WHEELPOSE_SOURCE_DIR) / "tests" / "fixtures" / "movenet" /
         ("frame" + std::to_string(index) + ".jpg");
}
// The COCO sample's skier: one large person, as in real photos.
fs::path skier_file() {
  return fs::path(WHEELPOSE_SHARED_DIR) / "data" / "coco-sample" / "000000000785.jpg";
}

// An image letterboxed to `size` on its longer side (RGB).
cv::Mat model_input(const fs::path& file, int size = 256) {
  const cv::Mat bgr = cv::imread(file.string(), cv::IMREAD_COLOR);
  cv::Mat rgb;
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  return letterbox_image(rgb, plan_letterbox(rgb.cols, rgb.rows, size));
}

class ModelExport : public ::testing::Test {
 protected:
  void SetUp() override {
    WHEELPOSE_REQUIRE_MODEL(kMultipose);
    torch::set_num_threads(2);
  }
};

TEST_F(ModelExport, Float16ExportHoldsTheTrainedWeightsRoundedAndRoundTripsByteForByte) {
  TempDir dir("export16");
  const fs::path pt = write_shifted_weights(dir.path() / "tuned.pt");
  const ModelChoice source = choose_model(pt.string(), testing::models_dir());
  const ExportSummary first = export_tfjs_model(source, dir.path() / "a", {});
  EXPECT_EQ(first.base_model, kMultipose);
  EXPECT_GT(first.parameters, 100u);
  EXPECT_GT(first.weights, first.parameters);  // the decoder's integer constants too

  GraphModule tuned(source.topology);
  tuned.load(pt);
  GraphModule exported(dir.path() / "a" / kExportTopology);
  EXPECT_EQ(exported.graph().name(), kMultipose);  // so .pt files trained from it load by name
  ASSERT_EQ(exported.parameter_nodes(), tuned.parameter_nodes());
  for (const std::string& node : tuned.parameter_nodes()) {
    const torch::Tensor rounded = tuned.parameter(node).detach().to(torch::kHalf).to(torch::kFloat);
    ASSERT_TRUE(torch::equal(exported.parameter(node).detach(), rounded)) << node;
  }
  // Same bytes again from the export itself.
  const ExportSummary second = export_tfjs_model(
      choose_model((dir.path() / "a" / kExportTopology).string(), {}), dir.path() / "b", {});
  EXPECT_EQ(second.bin_bytes, first.bin_bytes);
  for (const char* file : {kExportTopology, kExportShard}) {
    EXPECT_EQ(read_file(dir.path() / "a" / file), read_file(dir.path() / "b" / file)) << file;
  }
  // How far float16 rounding moves the outputs: information for the model card, not a bound
  // (a person's decoded position may jump to a neighbouring heatmap cell).
  const cv::Mat rgb = model_input(frame_file(0));
  const double moved = (run(exported, rgb) - run(tuned, rgb)).abs().max().item<double>();
  std::cout << "[ NOTE ] float16 rounding of the weights moves Identity:0 by at most " << moved
            << "\n";
}

TEST_F(ModelExport, Float32ExportIsExact) {
  TempDir dir("export32");
  const fs::path pt = write_shifted_weights(dir.path() / "tuned.pt");
  const ModelChoice source = choose_model(pt.string(), testing::models_dir());
  const ExportSummary s = export_tfjs_model(source, dir.path() / "a", {.float32 = true});
  const json doc = json::parse(read_file(dir.path() / "a" / kExportTopology));
  for (const json& w : doc["weightsManifest"][0]["weights"])
    EXPECT_FALSE(w.contains("quantization"));
  EXPECT_EQ(doc["signature"], json::parse(read_file(source.topology))["signature"]);
  EXPECT_EQ(fs::file_size(dir.path() / "a" / kExportShard), s.bin_bytes);
  GraphModule tuned(source.topology);
  tuned.load(pt);
  GraphModule exported(dir.path() / "a" / kExportTopology);
  const cv::Mat rgb = model_input(frame_file(1));
  EXPECT_TRUE(torch::equal(run(exported, rgb), run(tuned, rgb)));
}

TEST_F(ModelExport, BadInputsNameTheFileAndWriteNothing) {
  TempDir dir("export_bad");
  const fs::path pt = write_shifted_weights(dir.path() / "tuned.pt");
  const std::string bytes = read_file(pt);
  const fs::path truncated = dir.path() / "truncated.pt";
  std::ofstream(truncated, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  const fs::path out = dir.path() / "out";
  EXPECT_NE(error_of([&] {
              choose_model(truncated.string(), testing::models_dir());
            }).find("truncated.pt: not a weights file"),
            std::string::npos);
  // Weights that do not fit the model their file names.
  if (testing::have_model("movenet-lightning")) {
    GraphModule lightning(testing::model_json("movenet-lightning"));
    const fs::path other = dir.path() / "other.pt";
    lightning.save(other);
    const ModelChoice wrong{testing::model_json(kMultipose), other};
    EXPECT_NE(
        error_of([&] { export_tfjs_model(wrong, out, {}); }).find("other.pt: weights of model"),
        std::string::npos);
  }
  // An output folder that cannot be made (a file is in the way).
  std::ofstream(dir.path() / "file") << "x";
  const ModelChoice source = choose_model(pt.string(), testing::models_dir());
  EXPECT_NE(error_of([&] { export_tfjs_model(source, dir.path() / "file" / "out", {}); }), "");
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(ModelExport, BlendInterpolatesEveryParameter) {
  TempDir dir("blend");
  const fs::path pt = write_shifted_weights(dir.path() / "tuned.pt");
  const ModelChoice start{testing::model_json(kMultipose), std::nullopt};
  const ModelChoice tuned_choice{testing::model_json(kMultipose), pt};
  blend_weights(start, tuned_choice, {.alpha = 0.25, .part_alphas = {}}, dir.path() / "blend.pt");
  GraphModule pretrained(testing::model_json(kMultipose));
  GraphModule tuned(testing::model_json(kMultipose));
  tuned.load(pt);
  GraphModule blended(testing::model_json(kMultipose));
  blended.load(dir.path() / "blend.pt");
  for (const std::string& node : tuned.parameter_nodes()) {
    const torch::Tensor p0 = pretrained.parameter(node).detach();
    const torch::Tensor expected = p0 + 0.25 * (tuned.parameter(node).detach() - p0);
    ASSERT_TRUE(torch::allclose(blended.parameter(node).detach(), expected, 1e-6, 1e-7)) << node;
  }
  blend_weights(start, tuned_choice, {.alpha = 1.0, .part_alphas = {}}, dir.path() / "one.pt");
  GraphModule one(testing::model_json(kMultipose));
  one.load(dir.path() / "one.pt");
  for (const std::string& node : tuned.parameter_nodes()) {
    ASSERT_TRUE(torch::equal(one.parameter(node).detach(), tuned.parameter(node).detach()));
  }
  EXPECT_NE(error_of([&] {
              blend_weights(start, tuned_choice, {.alpha = 1.5, .part_alphas = {}},
                            dir.path() / "x.pt");
            }).find("alpha must be in [0, 1]"),
            std::string::npos);
  if (testing::have_model("movenet-lightning")) {
    const ModelChoice other{testing::model_json("movenet-lightning"), std::nullopt};
    EXPECT_NE(error_of([&] {
                blend_weights(start, other, {}, dir.path() / "x.pt");
              }).find("weights of model 'movenet-lightning', not of 'movenet-multipose'"),
              std::string::npos);
  }
  EXPECT_FALSE(fs::exists(dir.path() / "x.pt"));
}

// Per-part alphas: the backbone keeps the start's weights, the keypoint heads take the
// fine-tuned ones, everything else goes halfway; a part that names nothing is an error.
TEST_F(ModelExport, BlendTakesAnAlphaPerPart) {
  TempDir dir("blend-parts");
  const fs::path pt = write_shifted_weights(dir.path() / "tuned.pt");
  const ModelChoice start{testing::model_json(kMultipose), std::nullopt};
  const ModelChoice tuned_choice{testing::model_json(kMultipose), pt};
  const BlendAlphas alphas{.alpha = 0.5,
                           .part_alphas = {{"feature_extractor", 0.0}, {"/kpt_", 1.0}}};
  blend_weights(start, tuned_choice, alphas, dir.path() / "parts.pt");
  GraphModule pretrained(testing::model_json(kMultipose));
  GraphModule tuned(testing::model_json(kMultipose));
  tuned.load(pt);
  GraphModule blended(testing::model_json(kMultipose));
  blended.load(dir.path() / "parts.pt");
  int backbone = 0, keypoint_heads = 0, others = 0;
  for (const std::string& node : tuned.parameter_nodes()) {
    const torch::Tensor p0 = pretrained.parameter(node).detach();
    const torch::Tensor p1 = tuned.parameter(node).detach();
    const torch::Tensor got = blended.parameter(node).detach();
    if (node.find("feature_extractor") != std::string::npos) {
      ASSERT_TRUE(torch::equal(got, p0)) << node;
      ++backbone;
    } else if (node.find("/kpt_") != std::string::npos) {
      ASSERT_TRUE(torch::equal(got, p1)) << node;
      ++keypoint_heads;
    } else {
      ASSERT_TRUE(torch::allclose(got, p0 + 0.5 * (p1 - p0), 1e-6, 1e-7)) << node;
      ++others;
    }
  }
  EXPECT_GT(backbone, 0);
  EXPECT_GT(keypoint_heads, 0);
  EXPECT_GT(others, 0);
  const BlendAlphas typo{.alpha = 0.5, .part_alphas = {{"no_such_layer", 0.0}}};
  EXPECT_NE(error_of([&] {
              blend_weights(start, tuned_choice, typo, dir.path() / "x.pt");
            }).find("no parameter of movenet-multipose is named like 'no_such_layer'"),
            std::string::npos);
  EXPECT_FALSE(fs::exists(dir.path() / "x.pt"));
  // A part whose parameters an earlier, wider part already took: the message names that part.
  const BlendAlphas shadowed{
      .alpha = 0.5,
      .part_alphas = {{"feature_extractor", 0.0}, {"feature_extractor/model_1/conv2d/", 1.0}}};
  EXPECT_NE(error_of([&] { blend_weights(start, tuned_choice, shadowed, dir.path() / "x.pt"); })
                .find("--alpha-for feature_extractor/model_1/conv2d/ changes nothing: the earlier "
                      "--alpha-for feature_extractor already took its parameters"),
            std::string::npos);
  EXPECT_FALSE(fs::exists(dir.path() / "x.pt"));
}

// The real TF.js runtime (tests/tfjs_reference, set up by scripts/setup.sh) on the export agrees
// with LibTorch on the fine-tuned weights rounded to float16 (the export's precision).
TEST_F(ModelExport, TfjsRunsTheExportLikeLibTorch) {
  const fs::path runner_dir = fs::path(WHEELPOSE_SOURCE_DIR) / "tests" / "tfjs_reference";
  if (!fs::exists(runner_dir / "node_modules" / "@tensorflow") ||
      std::system("command -v node >/dev/null 2>&1") != 0) {
    if (std::getenv("CI")) FAIL() << "node and tests/tfjs_reference/node_modules are needed";
    GTEST_SKIP() << "needs node and npm ci in tests/tfjs_reference (scripts/setup.sh)";
  }
  TempDir dir("export_tfjs");
  const fs::path pt = write_shifted_weights(dir.path() / "tuned.pt");
  export_tfjs_model(choose_model(pt.string(), testing::models_dir()), dir.path() / "export", {});
  json manifest = {{"inputs", json::array()}};
  std::vector<cv::Mat> inputs;
  // The multipose inputs of the importer's TF.js fixture (movenet_reference_test.cpp): the five
  // frames and the skier at 256, two frames at 512. The skier last.
  std::vector<fs::path> files;
  std::vector<int> sizes;
  auto add = [&](const fs::path& file, int size) {
    files.push_back(file);
    sizes.push_back(size);
  };
  for (int i = 0; i < 5; ++i) add(frame_file(i), 256);
  for (int i = 0; i < 2; ++i) add(frame_file(i), 512);
  add(skier_file(), 256);
  for (std::size_t i = 0; i < files.size(); ++i) {
    if (!fs::exists(files[i])) GTEST_SKIP() << files[i] << " missing (shared test data)";
    inputs.push_back(model_input(files[i], sizes[i]));
    cv::Mat bgr;
    cv::cvtColor(inputs.back(), bgr, cv::COLOR_RGB2BGR);
    const std::string name = "input" + std::to_string(i) + ".png";
    ASSERT_TRUE(cv::imwrite((dir.path() / name).string(), bgr));
    manifest["inputs"].push_back(
        {{"file", name}, {"model", kMultipose}, {"topology", "export/model.json"}});
  }
  std::ofstream(dir.path() / "manifest.json") << manifest.dump();
  const std::string command = "cd '" + runner_dir.string() + "' && node reference.mjs --models '" +
                              testing::models_dir().string() + "' --inputs '" +
                              (dir.path() / "manifest.json").string() + "' --out '" +
                              (dir.path() / "tfjs.json").string() + "' --time-runs 0 2>/dev/null";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  const json fixture = json::parse(read_file(dir.path() / "tfjs.json"));
  GraphModule exported(dir.path() / "export" / kExportTopology);
  ASSERT_EQ(fixture["entries"].size(), inputs.size());
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    const torch::Tensor ours = run(exported, inputs[i]).to(torch::kFloat);
    const std::vector<double> theirs = fixture["entries"][i]["outputs"]["Identity:0"]["data"];
    ASSERT_EQ(static_cast<std::int64_t>(theirs.size()), ours.numel());
    const float* v = ours.data_ptr<float>();
    double worst = 0;
    for (std::int64_t k = 0; k < ours.numel(); ++k)
      worst = std::max(worst, std::abs(v[k] - theirs[k]));
    EXPECT_LE(worst, 1e-3) << files[i] << " at " << sizes[i];
    std::cout << "[ NOTE ] " << files[i].filename() << " at " << sizes[i]
              << ": TF.js and LibTorch differ by at most " << worst << "\n";
  }
  // The shifted weights still find the skier: the comparison is of a working model, not noise.
  EXPECT_GT(run(exported, inputs.back()).select(2, 55).max().item<double>(), 0.3);
}

}  // namespace
}  // namespace wheelpose::learn
