#include "learn/pose_predictor.h"

#include <torch/torch.h>

#include <algorithm>
#include <cmath>
#include <thread>

#include "core/error.h"
#include "learn/graph_module.h"
#include "learn/letterbox.h"
#include "learn/scale_merge.h"

namespace wheelpose::learn {
namespace {

constexpr int kKeypoints = 17;
constexpr int kMultiPeople = 6;
constexpr int kMultiValues = 56;  // 17 × (y, x, score) + ymin, xmin, ymax, xmax, score

// An RGB image (CV_8UC3, continuous) as the models' 1×H×W×3 int32 input.
torch::Tensor to_input(const cv::Mat& rgb) {
  const cv::Mat contiguous = rgb.isContinuous() ? rgb : rgb.clone();
  return torch::from_blob(contiguous.data, {1, contiguous.rows, contiguous.cols, 3}, torch::kUInt8)
      .to(torch::kInt32);
}

// Rounded to `per_unit`ths; dividing (not multiplying by 1 / per_unit) gives the double nearest
// the decimal, so the JSON holds 0.5901, not 0.5901000000000001.
double round_to(double v, double per_unit) { return std::round(v * per_unit) / per_unit; }

}  // namespace

nlohmann::json coco_result_json(std::int64_t image_id, const PosePrediction& p) {
  nlohmann::json keypoints = nlohmann::json::array();
  for (int k = 0; k < kKeypoints; ++k) {
    keypoints.push_back(round_to(p.keypoints[3 * k], 100));
    keypoints.push_back(round_to(p.keypoints[3 * k + 1], 100));
    keypoints.push_back(round_to(p.keypoints[3 * k + 2], 10000));
  }
  return {{"image_id", image_id},
          {"category_id", 1},
          {"keypoints", keypoints},
          {"score", round_to(p.score, 10000)},
          {"bbox",
           {round_to(p.bbox.x, 100), round_to(p.bbox.y, 100), round_to(p.bbox.w, 100),
            round_to(p.bbox.h, 100)}}};
}

struct PosePredictor::Impl {
  GraphModule graph;
  std::string output;
  bool multi = false;
  int crop = 0;
  PredictOptions options;

  Impl(const std::filesystem::path& model_json, const PredictOptions& o,
       const std::optional<std::filesystem::path>& weights)
      : graph(model_json), options(o) {
    if (weights) graph.load(*weights);
    const TfjsModel& m = graph.graph();
    if (m.outputs.size() != 1 || m.inputs.size() != 1) {
      throw Error(model_json.string() +
                  ": not a MoveNet model (expected one input and one output)");
    }
    output = m.outputs[0].name;
    const std::vector<std::int64_t>& out_shape = m.outputs[0].shape;
    const std::vector<std::int64_t>& in_shape = m.inputs[0].shape;
    if (out_shape == std::vector<std::int64_t>{1, kMultiPeople, kMultiValues}) {
      multi = true;
    } else if (out_shape == std::vector<std::int64_t>{1, 1, kKeypoints, 3} &&
               in_shape.size() == 4 && in_shape[1] > 0 && in_shape[1] == in_shape[2]) {
      crop = static_cast<int>(in_shape[1]);
    } else {
      throw Error(model_json.string() +
                  ": not a MoveNet model (output must be 1×6×56 or 1×1×17×3 with a square input)");
    }
    const int threads =
        o.threads > 0 ? o.threads : static_cast<int>(std::thread::hardware_concurrency());
    torch::set_num_threads(std::max(1, threads));
    graph.eval();
  }

  // The people of one letterboxed run, in image pixels, in the model's order.
  std::vector<PosePrediction> decode_people(const cv::Mat& rgb, const Letterbox& box) {
    const torch::Tensor out = run(letterbox_image(rgb, box));
    const float* v = out.data_ptr<float>();
    std::vector<PosePrediction> people;
    for (int j = 0; j < kMultiPeople; ++j) {
      const float* p = v + j * kMultiValues;
      if (p[55] < options.min_score) continue;
      PosePrediction person;
      for (int k = 0; k < kKeypoints; ++k) {
        const cv::Point2d at = letterbox_to_image(box, p[3 * k], p[3 * k + 1]);
        person.keypoints[3 * k] = at.x;
        person.keypoints[3 * k + 1] = at.y;
        person.keypoints[3 * k + 2] = p[3 * k + 2];
      }
      const cv::Point2d lo = letterbox_to_image(box, p[51], p[52]);
      const cv::Point2d hi = letterbox_to_image(box, p[53], p[54]);
      const double x0 = std::clamp(lo.x, 0.0, static_cast<double>(rgb.cols));
      const double y0 = std::clamp(lo.y, 0.0, static_cast<double>(rgb.rows));
      const double x1 = std::clamp(hi.x, 0.0, static_cast<double>(rgb.cols));
      const double y1 = std::clamp(hi.y, 0.0, static_cast<double>(rgb.rows));
      person.bbox = {x0, y0, std::max(0.0, x1 - x0), std::max(0.0, y1 - y0)};
      person.score = p[55];
      people.push_back(person);
    }
    return people;
  }

  torch::Tensor run(const cv::Mat& input) {
    torch::InferenceMode guard;
    return graph.forward(to_input(input)).at(output).to(torch::kFloat32).contiguous();
  }
};

PosePredictor::PosePredictor(const std::filesystem::path& model_json, const PredictOptions& options,
                             const std::optional<std::filesystem::path>& weights)
    : impl_(std::make_unique<Impl>(model_json, options, weights)) {}

PosePredictor::~PosePredictor() = default;

bool PosePredictor::multi_person() const { return impl_->multi; }
int PosePredictor::crop_size() const { return impl_->crop; }

std::vector<PosePrediction> PosePredictor::predict_image(const cv::Mat& rgb) const {
  WHEELPOSE_CHECK(impl_->multi && rgb.type() == CV_8UC3 && !impl_->options.longer_sides.empty());
  std::vector<ScaleResult> scales;
  for (const int longer_side : impl_->options.longer_sides) {
    const Letterbox box = plan_letterbox(rgb.cols, rgb.rows, longer_side);
    scales.push_back({box.scale, impl_->decode_people(rgb, box)});
  }
  if (scales.size() == 1) return scales[0].people;
  return merge_scales(scales, {.max_person_px = impl_->options.max_person_px});
}

std::vector<PosePrediction> PosePredictor::predict_boxes(
    const cv::Mat& rgb, const std::vector<coco::Box>& boxes) const {
  WHEELPOSE_CHECK(!impl_->multi && rgb.type() == CV_8UC3);
  std::vector<PosePrediction> people;
  for (const coco::Box& b : boxes) {
    const SquareCrop crop = square_around(b);
    const torch::Tensor out = impl_->run(crop_image(rgb, crop, impl_->crop));
    const float* p = out.data_ptr<float>();
    PosePrediction person;
    double sum = 0;
    for (int k = 0; k < kKeypoints; ++k) {
      const cv::Point2d at = crop_to_image(crop, p[3 * k], p[3 * k + 1]);
      person.keypoints[3 * k] = at.x;
      person.keypoints[3 * k + 1] = at.y;
      person.keypoints[3 * k + 2] = p[3 * k + 2];
      sum += p[3 * k + 2];
    }
    person.score = sum / kKeypoints;
    person.bbox = b;
    people.push_back(person);
  }
  return people;
}

}  // namespace wheelpose::learn
