#pragma once
// Fine-tuned weights files (.pt) written by GraphModule::save. Torch-free, so the app can tell
// which MoveNet model a .pt belongs to without including torch.

#include <filesystem>
#include <string>

namespace wheelpose::learn {

// The "format" field of a weights file.
inline constexpr const char* kWeightsFormat = "wheelpose.learn.weights";

// The name of the model (topology stem, e.g. "movenet-lightning") a weights file was saved
// from. Throws Error naming the file if it is not a weights file.
std::string weights_model_name(const std::filesystem::path& path);

}  // namespace wheelpose::learn
