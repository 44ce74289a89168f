#include "learn/model_export.h"

#include <torch/torch.h>

#include <algorithm>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/atomic_file.h"
#include "core/error.h"
#include "learn/graph_module.h"

namespace wheelpose::learn {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// The source model with the .pt's weights loaded when there is one.
std::shared_ptr<GraphModule> load_choice(const ModelChoice& choice) {
  auto module = std::make_shared<GraphModule>(choice.topology);
  if (choice.weights) module->load(*choice.weights);
  return module;
}

std::string tensor_bytes(const torch::Tensor& t) {
  const torch::Tensor c = t.contiguous();
  return std::string(static_cast<const char*>(c.data_ptr()), c.nbytes());
}

}  // namespace

ExportSummary export_tfjs_model(const ModelChoice& source, const fs::path& out_dir,
                                const ExportOptions& options) {
  const std::shared_ptr<GraphModule> loaded = load_choice(source);
  const GraphModule& module = *loaded;
  json doc;
  try {
    doc = json::parse(read_file(source.topology));
  } catch (const json::parse_error& e) {  // load_choice read it already; changed since?
    throw Error(source.topology.string() + ": corrupt JSON (" + e.what() + ")");
  }
  const TfjsModel& graph = module.graph();
  ExportSummary summary;
  summary.base_model = graph.name();
  std::vector<std::string> parameters(module.parameter_nodes());
  std::sort(parameters.begin(), parameters.end());

  std::string bin;
  json entries = json::array();
  for (const json& group : doc.at("weightsManifest")) {
    for (const json& entry : group.at("weights")) {
      const std::string name = entry.at("name").get<std::string>();
      torch::Tensor value = module.tf_value(name);
      json out = {{"name", name}, {"shape", entry.at("shape")}};
      if (value.scalar_type() == torch::kFloat) {
        out["dtype"] = "float32";
        if (!options.float32) {
          value = value.to(torch::kHalf);
          out["quantization"] = {{"dtype", "float16"}, {"original_dtype", "float32"}};
        }
      } else {
        out["dtype"] = entry.at("dtype");
      }
      bin += tensor_bytes(value);
      entries.push_back(std::move(out));
      ++summary.weights;
      summary.parameters += std::binary_search(parameters.begin(), parameters.end(), name);
    }
  }
  doc["weightsManifest"] = json::array({{{"paths", {kExportShard}}, {"weights", entries}}});
  doc["convertedBy"] = "wheelpose model export";
  doc["userDefinedMetadata"]["wheelpose"]["base_model"] = summary.base_model;
  summary.bin_bytes = bin.size();

  // An output folder that cannot be made or written is the user's to fix (--out): exit 2.
  std::optional<AtomicFileWriter> shard, topology;
  try {
    ensure_directory(out_dir);
    shard.emplace(out_dir / kExportShard);
    topology.emplace(out_dir / kExportTopology);
  } catch (const Error& e) {
    throw Error(std::string(e.what()) + " (--out)");
  }
  shard->write(bin);
  topology->write(doc.dump() + "\n");
  shard->commit();
  topology->commit();
  return summary;
}

void blend_weights(const ModelChoice& start, const ModelChoice& finetuned,
                   const BlendAlphas& alphas, const fs::path& out_pt) {
  const auto check_alpha = [](double alpha, const std::string& where) {
    if (!(alpha >= 0 && alpha <= 1)) {
      throw Error("blend: " + where + " must be in [0, 1], got " + std::to_string(alpha));
    }
  };
  check_alpha(alphas.alpha, "alpha");
  for (const auto& [part, alpha] : alphas.part_alphas)
    check_alpha(alpha, "alpha of '" + part + "'");
  const std::shared_ptr<GraphModule> start_module = load_choice(start);
  const std::shared_ptr<GraphModule> tuned_module = load_choice(finetuned);
  GraphModule& base = *start_module;
  const GraphModule& tuned = *tuned_module;
  const std::string what =
      finetuned.weights ? finetuned.weights->string() : finetuned.topology.string();
  if (tuned.graph().name() != base.graph().name() ||
      tuned.parameter_nodes() != base.parameter_nodes()) {
    throw Error(what + ": weights of model '" + tuned.graph().name() + "', not of '" +
                base.graph().name() + "'");
  }
  std::vector<bool> part_used(alphas.part_alphas.size(), false);
  const auto alpha_of = [&](const std::string& node) {
    for (std::size_t i = 0; i < alphas.part_alphas.size(); ++i) {
      if (node.find(alphas.part_alphas[i].first) != std::string::npos) {
        part_used[i] = true;
        return alphas.part_alphas[i].second;
      }
    }
    return alphas.alpha;
  };
  torch::NoGradGuard no_grad;
  for (const std::string& node : base.parameter_nodes()) {
    const torch::Tensor target = tuned.parameter(node);
    torch::Tensor p = base.parameter(node);
    if (!p.sizes().equals(target.sizes())) {
      throw Error(what + ": parameter '" + node + "' has another shape than in the start model");
    }
    p.lerp_(target, alpha_of(node));
  }
  for (std::size_t i = 0; i < part_used.size(); ++i) {
    if (part_used[i]) continue;
    const std::string& part = alphas.part_alphas[i].first;
    // Named parameters, all claimed by an earlier (first-match-wins) part: say which.
    for (const std::string& node : base.parameter_nodes()) {
      if (node.find(part) == std::string::npos) continue;
      for (std::size_t j = 0; j < i; ++j) {
        if (node.find(alphas.part_alphas[j].first) != std::string::npos) {
          throw Error("blend: --alpha-for " + part + " changes nothing: the earlier --alpha-for " +
                      alphas.part_alphas[j].first + " already took its parameters (e.g. '" + node +
                      "'); the first match wins, so give the narrower part first");
        }
      }
    }
    throw Error("blend: no parameter of " + base.graph().name() + " is named like '" + part + "'");
  }
  base.save(out_pt);
}

}  // namespace wheelpose::learn
