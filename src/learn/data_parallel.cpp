#include "learn/data_parallel.h"

#include <charconv>
#include <torch/csrc/distributed/c10d/FileStore.hpp>
#include <torch/csrc/distributed/c10d/ProcessGroupGloo.hpp>
#include <torch/csrc/distributed/c10d/TCPStore.hpp>

#include "core/error.h"

namespace wheelpose::learn {
namespace {

// The c10d store the processes meet at.
c10::intrusive_ptr<c10d::Store> open_store(const std::string& rendezvous, int rank,
                                           int world_size) {
  const std::string file = "file://", tcp = "tcp://";
  if (rendezvous.rfind(file, 0) == 0 && rendezvous.size() > file.size()) {
    return c10::make_intrusive<c10d::FileStore>(rendezvous.substr(file.size()), world_size);
  }
  if (rendezvous.rfind(tcp, 0) == 0) {
    const std::string address = rendezvous.substr(tcp.size());
    const std::size_t colon = address.rfind(':');
    int port = 0;
    const char* end = address.data() + address.size();
    if (colon != std::string::npos && colon > 0) {
      const auto [at, ec] = std::from_chars(address.data() + colon + 1, end, port);
      if (ec == std::errc() && at == end && port > 0 && port < 65536) {
        c10d::TCPStoreOptions options;
        options.port = static_cast<std::uint16_t>(port);
        options.isServer = rank == 0;
        options.numWorkers = static_cast<std::size_t>(world_size);
        return c10::make_intrusive<c10d::TCPStore>(address.substr(0, colon), options);
      }
    }
  }
  throw Error("--rendezvous " + rendezvous + ": expected tcp://HOST:PORT or file:///PATH");
}

}  // namespace

GradientAverager::GradientAverager(const std::string& rendezvous, int rank, int world_size)
    : world_size_(world_size) {
  try {
    auto options = c10d::ProcessGroupGloo::Options::create();
    options->devices.push_back(c10d::ProcessGroupGloo::createDefaultDevice());
    group_ = std::make_unique<c10d::ProcessGroupGloo>(open_store(rendezvous, rank, world_size),
                                                      rank, world_size, options);
  } catch (const c10::Error& e) {
    throw Error("--rendezvous " + rendezvous + ": cannot join as rank " + std::to_string(rank) +
                    " of " + std::to_string(world_size) + " (" +
                    std::string(e.what_without_backtrace()).substr(0, 200) + ")",
                ErrorKind::kFailure);
  }
}

GradientAverager::~GradientAverager() = default;

void GradientAverager::average(const std::vector<torch::Tensor>& parameters, StepReport& parts) {
  std::vector<torch::Tensor> pieces;
  for (const torch::Tensor& p : parameters) {
    const torch::Tensor g = p.grad();
    pieces.push_back(g.defined() ? g.reshape({-1}) : torch::zeros({p.numel()}));
  }
  double* const fields[] = {&parts.loss,
                            &parts.centre,
                            &parts.keypoint_heatmap,
                            &parts.keypoint_regression,
                            &parts.keypoint_offset,
                            &parts.box_scale,
                            &parts.box_offset,
                            &parts.distill};
  std::vector<float> values;
  for (double* f : fields) values.push_back(static_cast<float>(*f));
  pieces.push_back(torch::tensor(values, torch::kFloat));
  std::vector<torch::Tensor> flat = {torch::cat(pieces)};
  group_->allreduce(flat)->wait();
  flat[0].div_(world_size_);
  std::int64_t at = 0;
  for (const torch::Tensor& p : parameters) {
    const std::int64_t n = p.numel();
    if (p.grad().defined()) p.mutable_grad().copy_(flat[0].slice(0, at, at + n).view_as(p));
    at += n;
  }
  for (double* f : fields) *f = flat[0][at++].item<double>();
}

void GradientAverager::barrier() { group_->barrier()->wait(); }

}  // namespace wheelpose::learn
