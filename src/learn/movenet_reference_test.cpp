// Our MoveNet execution against the real TF.js runtime. tests/fixtures/movenet/ holds five of
// our generated frames; with the COCO sample image from the shared data they make the inputs
// (model_input below). tests/tfjs_reference/make_fixture.sh writes those inputs as PNGs
// (WHEELPOSE_WRITE_TFJS_INPUTS=DIR runs ReferenceInputs.Write), runs @tensorflow/tfjs on them
// and stores the outputs in tests/fixtures/movenet/tfjs_reference.json, which this test
// compares with: keypoint coordinates and scores within 1e-3 for all three models.

#include <gtest/gtest.h>
#include <torch/torch.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "learn/graph_module.h"
#include "learn/letterbox.h"

namespace wheelpose::learn {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

fs::path source_dir() { return fs::path(WHEELPOSE_SOURCE_DIR); }
fs::path fixture_dir() { return source_dir() / "tests" / "fixtures" / "movenet"; }

fs::path models_dir() {
  if (const char* env = std::getenv("WHEELPOSE_MODELS"); env && *env) return env;
  return source_dir() / "models";
}

fs::path shared_dir() { return fs::path(WHEELPOSE_SHARED_DIR); }

struct ReferenceInput {
  std::string name;   // PNG file name
  std::string model;  // movenet-…
  fs::path image;
  int size;  // multipose: longer side; single-person: the square side
};

// Every model on every image; multipose also at 512 on two frames.
std::vector<ReferenceInput> reference_inputs() {
  std::vector<fs::path> images;
  for (int i = 0; i < 5; ++i)
    images.push_back(fixture_dir() / ("frame" + std::to_string(i) + ".jpg"));
  images.push_back(shared_dir() / "data" / "coco-sample" / "000000000785.jpg");
  std::vector<ReferenceInput> inputs;
  for (std::size_t i = 0; i < images.size(); ++i) {
    const std::string stem = images[i].stem().string();
    inputs.push_back({stem + "_multipose256.png", "movenet-multipose", images[i], 256});
    inputs.push_back({stem + "_lightning192.png", "movenet-lightning", images[i], 192});
    inputs.push_back({stem + "_thunder256.png", "movenet-thunder", images[i], 256});
    if (i < 2) inputs.push_back({stem + "_multipose512.png", "movenet-multipose", images[i], 512});
  }
  return inputs;
}

// The network input (RGB): multipose letterboxed to the longer side; single-person letterboxed
// and padded to a square.
cv::Mat model_input(const ReferenceInput& in) {
  const cv::Mat bgr = cv::imread(in.image.string(), cv::IMREAD_COLOR);
  if (bgr.empty()) return {};
  cv::Mat rgb;
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  const cv::Mat boxed = letterbox_image(rgb, plan_letterbox(rgb.cols, rgb.rows, in.size));
  if (in.model == "movenet-multipose") return boxed;
  cv::Mat square;
  cv::copyMakeBorder(boxed, square, 0, in.size - boxed.rows, 0, in.size - boxed.cols,
                     cv::BORDER_CONSTANT, cv::Scalar::all(0));
  return square;
}

// FNV-1a 64 of the RGB bytes: the fixture's inputs must be the ones this test builds.
std::string fingerprint(const cv::Mat& rgb) {
  std::uint64_t h = 1469598103934665603ull;
  const cv::Mat c = rgb.isContinuous() ? rgb : rgb.clone();
  for (std::size_t i = 0; i < c.total() * c.elemSize(); ++i) {
    h = (h ^ c.data[i]) * 1099511628211ull;
  }
  std::ostringstream s;
  s << std::hex << h;
  return s.str();
}

bool have_inputs() {
  return fs::exists(models_dir() / "movenet-multipose.json") &&
         fs::exists(shared_dir() / "data" / "coco-sample" / "000000000785.jpg");
}

// Writes the inputs and manifest.json for tests/tfjs_reference/reference.mjs.
TEST(ReferenceInputs, Write) {
  const char* out = std::getenv("WHEELPOSE_WRITE_TFJS_INPUTS");
  if (!out || !*out) GTEST_SKIP() << "set WHEELPOSE_WRITE_TFJS_INPUTS=DIR to write the inputs";
  ASSERT_TRUE(have_inputs());
  fs::create_directories(out);
  json manifest = {{"inputs", json::array()}};
  for (const ReferenceInput& in : reference_inputs()) {
    const cv::Mat rgb = model_input(in);
    ASSERT_FALSE(rgb.empty()) << in.image;
    cv::Mat bgr;
    cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
    ASSERT_TRUE(cv::imwrite((fs::path(out) / in.name).string(), bgr));
    manifest["inputs"].push_back(
        {{"file", in.name}, {"model", in.model}, {"fnv1a", fingerprint(rgb)}});
  }
  std::ofstream(fs::path(out) / "manifest.json") << manifest.dump(2) << "\n";
}

TEST(TfjsReference, AllThreeModelsMatchTfjsWithin1e3) {
  if (!have_inputs()) GTEST_SKIP() << "models or shared data missing: run scripts/setup.sh";
  const fs::path fixture = fixture_dir() / "tfjs_reference.json";
  const fs::path manifest_path = fixture_dir() / "manifest.json";
  ASSERT_TRUE(fs::exists(fixture)) << fixture;
  const json reference = json::parse(std::ifstream(fixture));
  const json manifest = json::parse(std::ifstream(manifest_path));
  std::map<std::string, std::string> expected_fingerprint;
  for (const json& e : manifest["inputs"]) expected_fingerprint[e["file"]] = e["fnv1a"];
  std::map<std::string, ReferenceInput> by_name;
  for (const ReferenceInput& in : reference_inputs()) by_name[in.name] = in;

  torch::set_num_threads(2);
  std::map<std::string, std::unique_ptr<GraphModule>> models;
  int compared = 0;
  std::map<std::string, int> per_model;
  for (const json& entry : reference["entries"]) {
    const std::string file = entry["file"];
    ASSERT_TRUE(by_name.count(file)) << file << " is not an input this test builds";
    const ReferenceInput& in = by_name.at(file);
    const cv::Mat rgb = model_input(in);
    ASSERT_EQ(fingerprint(rgb), expected_fingerprint.at(file))
        << file << ": the input differs from the one TF.js saw (decoder or resize changed?)";
    auto& model = models[in.model];
    if (!model) model = std::make_unique<GraphModule>(models_dir() / (in.model + ".json"));
    torch::InferenceMode guard;
    const torch::Tensor input =
        torch::from_blob(rgb.clone().data, {1, rgb.rows, rgb.cols, 3}, torch::kUInt8)
            .to(torch::kInt32);
    const torch::Tensor ours =
        model->forward(input).at("Identity:0").to(torch::kFloat32).contiguous();
    const json& theirs = entry["outputs"]["Identity:0"];
    std::vector<std::int64_t> shape = theirs["shape"];
    ASSERT_EQ(ours.sizes().vec(), shape) << file;
    const std::vector<double> data = theirs["data"];
    ASSERT_EQ(static_cast<std::int64_t>(data.size()), ours.numel()) << file;
    const float* v = ours.data_ptr<float>();
    double worst = 0;
    std::int64_t worst_at = 0;
    for (std::int64_t i = 0; i < ours.numel(); ++i) {
      const double d = std::abs(v[i] - data[i]);
      if (d > worst) {
        worst = d;
        worst_at = i;
      }
    }
    EXPECT_LE(worst, 1e-3) << file << " (" << in.model << "): largest difference " << worst
                           << " at value " << worst_at << " (ours " << v[worst_at] << ", TF.js "
                           << data[worst_at] << ")";
    ++compared;
    ++per_model[in.model];
  }
  EXPECT_GE(per_model["movenet-multipose"], 6);
  EXPECT_GE(per_model["movenet-lightning"], 6);
  EXPECT_GE(per_model["movenet-thunder"], 6);
  std::cout << "[ NOTE ] compared " << compared << " outputs with TF.js\n";
}

}  // namespace
}  // namespace wheelpose::learn
