#include "learn/train_probe.h"

#include <thread>

#include "learn/graph_module.h"
#include "learn/train_step.h"
#include "learn/trainer.h"

namespace wheelpose::learn {

struct TrainStepProbe::Impl {
  GraphModule model;
  TrainBatch batch;
  torch::optim::AdamW optimizer;
  int steps = 0;

  Impl(const std::filesystem::path& model_json, const std::vector<TrainSample>& samples,
       int input_size)
      : model(model_json),
        // The targets `train` builds by default (offsets around each keypoint included).
        batch(make_train_batch(samples, input_size, TrainOptions{}.offset_radius)),
        optimizer(model.parameters(), torch::optim::AdamWOptions(1e-5)) {}
};

TrainStepProbe::TrainStepProbe(const std::filesystem::path& model_json,
                               const std::vector<TrainSample>& samples, int input_size,
                               bool channels_last, int threads)
    : impl_(std::make_unique<Impl>(model_json, samples, input_size)) {
  torch::set_num_threads(threads > 0 ? threads
                                     : static_cast<int>(std::thread::hardware_concurrency()));
  impl_->model.set_channels_last(channels_last);
  impl_->model.train();
}

TrainStepProbe::~TrainStepProbe() = default;

double TrainStepProbe::step() {
  return optimizer_step(impl_->model, impl_->optimizer, impl_->batch, 5.0, ++impl_->steps).loss;
}

}  // namespace wheelpose::learn
