#include "motion/glb_file.h"

#include <assimp/scene.h>

#include <algorithm>
#include <assimp/Exporter.hpp>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <vector>

#include "core/atomic_file.h"
#include "core/error.h"

namespace wheelpose::motion {

namespace {

std::uint32_t read_u32(const std::vector<std::uint8_t>& bytes, std::size_t at) {
  return static_cast<std::uint32_t>(bytes[at]) | static_cast<std::uint32_t>(bytes[at + 1]) << 8 |
         static_cast<std::uint32_t>(bytes[at + 2]) << 16 |
         static_cast<std::uint32_t>(bytes[at + 3]) << 24;
}

// Assimp 5.2.5 leaves uninitialised heap bytes in the gaps between buffer views of the binary
// chunk, so two exports of the same scene differ. Zeroing every byte no buffer view covers makes
// the file a pure function of the scene without changing what any reader sees.
void zero_unreferenced_glb_bytes(std::vector<std::uint8_t>& glb) {
  constexpr std::uint32_t kJson = 0x4E4F534A;  // "JSON"
  constexpr std::uint32_t kBin = 0x004E4942;   // "BIN\0"
  // Header (12 bytes), then chunks of {length, type, data}.
  if (glb.size() < 20 || read_u32(glb, 16) != kJson) return;
  const std::size_t json_length = read_u32(glb, 12);
  const std::size_t bin_header = 20 + json_length;
  if (glb.size() < bin_header + 8 || read_u32(glb, bin_header + 4) != kBin) return;
  const std::size_t bin_start = bin_header + 8;
  const std::size_t bin_length =
      std::min<std::size_t>(read_u32(glb, bin_header), glb.size() - bin_start);
  const auto json = nlohmann::json::parse(glb.begin() + 20, glb.begin() + 20 + json_length, nullptr,
                                          /*allow_exceptions=*/false);
  if (json.is_discarded() || !json.contains("bufferViews")) return;
  std::vector<bool> used(bin_length, false);
  for (const auto& view : json["bufferViews"]) {
    const std::size_t offset = view.value("byteOffset", std::size_t{0});
    const std::size_t length = view.value("byteLength", std::size_t{0});
    for (std::size_t i = offset; i < std::min(offset + length, bin_length); ++i) used[i] = true;
  }
  for (std::size_t i = 0; i < bin_length; ++i) {
    if (!used[i]) glb[bin_start + i] = 0;
  }
}

}  // namespace

void write_glb_file(const aiScene& scene, const std::filesystem::path& path) {
  Assimp::Exporter exporter;
  const aiExportDataBlob* blob = exporter.ExportToBlob(&scene, "glb2");
  if (blob == nullptr) {
    const std::string reason = exporter.GetErrorString();
    throw Error(path.string() +
                    ": glTF export failed: " + (reason.empty() ? "Assimp gave no reason" : reason),
                ErrorKind::kFailure);
  }
  // A glb is a single file; Assimp returns any extra files in blob->next.
  const auto* data = static_cast<const std::uint8_t*>(blob->data);
  std::vector<std::uint8_t> bytes(data, data + blob->size);
  zero_unreferenced_glb_bytes(bytes);
  write_file_atomic(path, std::span<const std::uint8_t>(bytes));
}

int GlbBuilder::add_accessor(std::span<const std::uint8_t> bytes, std::size_t count,
                             ComponentType component, const char* type, Target target,
                             const std::vector<float>& min, const std::vector<float>& max) {
  nlohmann::ordered_json view = {
      {"buffer", 0}, {"byteOffset", bin_.size()}, {"byteLength", bytes.size()}};
  if (target != kNoTarget) view["target"] = static_cast<int>(target);
  views_.push_back(std::move(view));
  bin_.insert(bin_.end(), bytes.begin(), bytes.end());
  bin_.resize((bin_.size() + 3) / 4 * 4, 0);  // every view starts 4-byte aligned
  nlohmann::ordered_json accessor = {{"bufferView", views_.size() - 1},
                                     {"componentType", static_cast<int>(component)},
                                     {"count", count},
                                     {"type", type}};
  if (!min.empty()) accessor["min"] = min;
  if (!max.empty()) accessor["max"] = max;
  accessors_.push_back(std::move(accessor));
  return static_cast<int>(accessors_.size() - 1);
}

void GlbBuilder::write(const std::filesystem::path& path) const {
  nlohmann::ordered_json document = json;
  document["accessors"] = accessors_;
  document["bufferViews"] = views_;
  document["buffers"] = nlohmann::ordered_json::array({{{"byteLength", bin_.size()}}});
  std::string text = document.dump();
  text.resize((text.size() + 3) / 4 * 4, ' ');  // the JSON chunk is padded with spaces
  std::vector<std::uint8_t> glb;
  auto put_u32 = [&glb](std::uint32_t v) {
    for (int i = 0; i < 4; ++i) glb.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  };
  put_u32(0x46546C67);  // "glTF"
  put_u32(2);
  put_u32(static_cast<std::uint32_t>(12 + 8 + text.size() + 8 + bin_.size()));
  put_u32(static_cast<std::uint32_t>(text.size()));
  put_u32(0x4E4F534A);  // "JSON"
  glb.insert(glb.end(), text.begin(), text.end());
  put_u32(static_cast<std::uint32_t>(bin_.size()));
  put_u32(0x004E4942);  // "BIN\0"
  glb.insert(glb.end(), bin_.begin(), bin_.end());
  write_file_atomic(path, std::span<const std::uint8_t>(glb));
}

}  // namespace wheelpose::motion
