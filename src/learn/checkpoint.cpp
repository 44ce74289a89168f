#include "learn/checkpoint.h"

#include <sstream>

#include "core/atomic_file.h"
#include "core/error.h"

namespace wheelpose::learn {
namespace fs = std::filesystem;
using torch::Tensor;

namespace {

// LibTorch keys an optimizer's state by each parameter's address, and its own save() writes the
// state in hash order with those addresses: the bytes change from run to run. This writes it per
// (group, parameter index) instead, so the same run gives the same checkpoint.
std::string state_key(const Tensor& parameter) {
  return c10::guts::to_string(parameter.unsafeGetTensorImpl());
}

std::string state_prefix(std::size_t group, std::size_t index) {
  return "adamw/" + std::to_string(group) + "/" + std::to_string(index) + "/";
}

void write_optimizer_state(torch::serialize::OutputArchive& archive,
                           const torch::optim::AdamW& optimizer) {
  const auto& groups = optimizer.param_groups();
  for (std::size_t g = 0; g < groups.size(); ++g) {
    const std::vector<Tensor>& params = groups[g].params();
    for (std::size_t i = 0; i < params.size(); ++i) {
      const auto found = optimizer.state().find(state_key(params[i]));
      if (found == optimizer.state().end()) continue;  // not stepped yet (frozen so far)
      const auto& state = static_cast<const torch::optim::AdamWParamState&>(*found->second);
      const std::string prefix = state_prefix(g, i);
      archive.write(prefix + "step", torch::tensor(state.step()));
      archive.write(prefix + "exp_avg", state.exp_avg());
      archive.write(prefix + "exp_avg_sq", state.exp_avg_sq());
      if (state.max_exp_avg_sq().defined()) {
        archive.write(prefix + "max_exp_avg_sq", state.max_exp_avg_sq());
      }
    }
  }
}

void read_optimizer_state(torch::serialize::InputArchive& archive, torch::optim::AdamW& optimizer) {
  const auto& groups = optimizer.param_groups();
  for (std::size_t g = 0; g < groups.size(); ++g) {
    const std::vector<Tensor>& params = groups[g].params();
    for (std::size_t i = 0; i < params.size(); ++i) {
      const std::string prefix = state_prefix(g, i);
      Tensor step, exp_avg, exp_avg_sq, max_exp_avg_sq;
      if (!archive.try_read(prefix + "step", step)) continue;
      archive.read(prefix + "exp_avg", exp_avg);
      archive.read(prefix + "exp_avg_sq", exp_avg_sq);
      auto state = std::make_unique<torch::optim::AdamWParamState>();
      state->step(step.item<std::int64_t>());
      state->exp_avg(exp_avg);
      state->exp_avg_sq(exp_avg_sq);
      if (archive.try_read(prefix + "max_exp_avg_sq", max_exp_avg_sq)) {
        state->max_exp_avg_sq(max_exp_avg_sq);
      }
      optimizer.state()[state_key(params[i])] = std::move(state);
    }
  }
}

}  // namespace

void save_checkpoint(GraphModule& model, torch::optim::AdamW& optimizer, int step,
                     const std::string& resume_key, const fs::path& out_dir) {
  torch::serialize::OutputArchive archive;
  for (const auto& p : model.named_parameters()) archive.write("model/" + p.key(), p.value());
  write_optimizer_state(archive, optimizer);
  archive.write("step", torch::tensor(static_cast<std::int64_t>(step)));
  archive.write("resume_key", c10::IValue(resume_key));
  std::ostringstream bytes;
  archive.save_to(bytes);
  model.save(out_dir / "last.pt");
  write_file_atomic(out_dir / "checkpoint.pt", bytes.str());
}

int load_checkpoint(GraphModule& model, torch::optim::AdamW& optimizer,
                    const std::string& resume_key, const fs::path& out_dir) {
  const fs::path path = out_dir / "checkpoint.pt";
  if (!fs::exists(path)) throw Error(path.string() + ": no checkpoint to resume from");
  torch::serialize::InputArchive archive;
  try {
    archive.load_from(path.string());
    c10::IValue stored_key;
    archive.read("resume_key", stored_key);
    if (!stored_key.isString() || stored_key.toStringRef() != resume_key) {
      throw Error(path.string() + ": written with other settings; resume needs the same " +
                  "--train, --model, --steps, --batch, --lr, --seed, … as the first run (see " +
                  (out_dir / "options.json").string() + ")");
    }
    torch::NoGradGuard no_grad;
    for (auto& p : model.named_parameters()) {
      Tensor value;
      archive.read("model/" + p.key(), value);
      p.value().copy_(value);
    }
    torch::serialize::InputArchive legacy_optimizer;  // LibTorch's own format, before 2026-12
    if (archive.try_read("optimizer", legacy_optimizer)) {
      optimizer.load(legacy_optimizer);
    } else {
      read_optimizer_state(archive, optimizer);
    }
    Tensor step;
    archive.read("step", step);
    return static_cast<int>(step.item<std::int64_t>());
  } catch (const c10::Error& e) {
    throw Error(path.string() + ": not a checkpoint of this model (" +
                std::string(e.what_without_backtrace()).substr(0, 160) + ")");
  }
}

}  // namespace wheelpose::learn
