#pragma once
// The one place an Assimp scene becomes a .glb file: the motion clip export, the static person
// and chair exports and the rigged person all write through it, so they share its determinism
// fix and its atomic write.

#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <span>
#include <vector>

struct aiScene;

namespace wheelpose::motion {

// Exports `scene` as binary glTF 2.0, zeroes the bytes Assimp leaves uninitialised (so equal
// scenes give equal files) and writes `path` atomically. Throws Error (kFailure) naming `path`
// when Assimp refuses the scene.
void write_glb_file(const aiScene& scene, const std::filesystem::path& path);

// A glTF 2.0 document written directly, for what Assimp's exporter gets wrong (it welds the
// vertices of skinned meshes and then loses bone weights): the caller fills `json` (nodes,
// meshes, ...) and adds binary data through add_accessor; write() assembles the .glb.
class GlbBuilder {
 public:
  enum ComponentType : int { kUnsignedByte = 5121, kUnsignedInt = 5125, kFloat = 5126 };
  enum Target : int { kNoTarget = 0, kVertices = 34962, kIndices = 34963 };
  // Appends `bytes` as one buffer view (4-byte aligned) and returns the accessor's index.
  // `type` is "SCALAR", "VEC3", ...; min/max, when given, are written as they are.
  int add_accessor(std::span<const std::uint8_t> bytes, std::size_t count, ComponentType component,
                   const char* type, Target target = kNoTarget, const std::vector<float>& min = {},
                   const std::vector<float>& max = {});
  template <typename T>
  int add_accessor(const std::vector<T>& values, std::size_t count, ComponentType component,
                   const char* type, Target target = kNoTarget, const std::vector<float>& min = {},
                   const std::vector<float>& max = {}) {
    return add_accessor(
        std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(values.data()),
                                      values.size() * sizeof(T)),
        count, component, type, target, min, max);
  }
  nlohmann::ordered_json json;  // everything but accessors, bufferViews and buffers
  // Writes the .glb atomically (same document, same bytes).
  void write(const std::filesystem::path& path) const;

 private:
  nlohmann::ordered_json accessors_ = nlohmann::ordered_json::array();
  nlohmann::ordered_json views_ = nlohmann::ordered_json::array();
  std::vector<std::uint8_t> bin_;
};

}  // namespace wheelpose::motion
