#pragma once
// Fine-tuned MoveNet weights back into a TF.js graph model, and weight-space blends of two
// models. Torch-free, so the app may include it.
//
// export_tfjs_model writes OUT/model.json and OUT/group1-shard1of1.bin: the source model's
// topology and signature unchanged (anything that loads MoveNet MultiPose loads it), one weight
// shard holding every manifest entry in the source's order, float32 weights stored as float16
// (like the published MoveNet models) unless `float32`. userDefinedMetadata.wheelpose.base_model
// names the MoveNet model it derives from, so weights trained from the export load by name.
// The result is a pure function of the weights: exporting an export gives the same bytes.

#include <cstddef>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "learn/model_files.h"

namespace wheelpose::learn {

struct ExportOptions {
  bool float32 = false;  // store float weights as float32 instead of float16
};

struct ExportSummary {
  std::string base_model;      // e.g. "movenet-multipose"
  std::size_t weights = 0;     // manifest entries written
  std::size_t parameters = 0;  // of which trainable (taken from the .pt when there is one)
  std::size_t bin_bytes = 0;
};

// The two files export_tfjs_model writes into its folder.
inline constexpr const char* kExportTopology = "model.json";
inline constexpr const char* kExportShard = "group1-shard1of1.bin";

// Writes `source` (a TF.js model, with a fine-tuned .pt's weights when it has one) to
// out_dir. Both files appear together or not at all; a folder that cannot be written, weights
// of another model or a corrupt source throw Error naming the file.
ExportSummary export_tfjs_model(const ModelChoice& source, const std::filesystem::path& out_dir,
                                const ExportOptions& options);

// How far toward the fine-tuned weights each parameter moves. `alpha` for all of them, except
// parameters whose node name contains one of `part_alphas`' names (the first that matches
// wins), e.g. {"feature_extractor", 0.3} to keep more of the start's backbone than its heads.
struct BlendAlphas {
  double alpha = 0.5;
  std::vector<std::pair<std::string, double>> part_alphas;
};

// Weight-space interpolation (WiSE-FT, Wortsman et al. 2022): every trainable parameter becomes
// start + alpha * (finetuned - start), saved as a .pt of the start's model. alpha 0 gives the
// start's weights, 1 the fine-tuned ones. Both must be the same MoveNet model; an alpha outside
// [0, 1] or a part name that matches no parameter throws Error.
void blend_weights(const ModelChoice& start, const ModelChoice& finetuned,
                   const BlendAlphas& alphas, const std::filesystem::path& out_pt);

}  // namespace wheelpose::learn
