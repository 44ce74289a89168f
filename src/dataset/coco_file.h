#pragma once
// COCO person-keypoint files as raw JSON, the canonical form every `coco` tool writes, and a
// validator that reports every problem with its JSON path.
//
// Canonical form (so that equal datasets are equal bytes, e.g. merged shards == one process):
//   - the top-level object's keys in byte order, one per line: `"key": value`;
//   - every top-level array written one element per line, each element compact;
//   - object keys inside elements in byte order; integers as integers; other numbers in the
//     shortest text that reads back to the same double (nlohmann-json's dump);
//   - images sorted by id, annotations by (image_id, id), categories by id;
//   - UTF-8, "\n" line ends, a final newline.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace wheelpose::dataset {

using nlohmann::json;

// Parses a JSON file; malformed JSON throws Error naming the file, line and byte.
json load_json(const std::filesystem::path& path);

// The canonical text written member by member, for files too large to hold (generate streams
// annotations.json from its per-frame fragments through it). The caller gives the top-level
// keys in byte order and array elements in their final order; canonical_coco_text writes
// through it too, so both give the same bytes.
class CanonicalCocoWriter {
 public:
  explicit CanonicalCocoWriter(std::function<void(const std::string&)> sink);
  void member(const std::string& key, const json& value);  // a whole member
  void begin_array(const std::string& key);                // or one element at a time
  void element(const json& value);
  void end_array();
  void finish();  // the closing brace and final newline

 private:
  void key(const std::string& name);
  std::function<void(const std::string&)> sink_;
  bool first_member_ = true, array_empty_ = true;
};

// The canonical text of a COCO object (sorting its arrays as above).
std::string canonical_coco_text(json root);
// Writes canonical_coco_text atomically.
void write_coco(const std::filesystem::path& path, json root);

// Integer value of `v` (785 or 785.0), nullopt if it is not an integral number.
std::optional<std::int64_t> as_integer(const json& v);

struct Problem {
  enum class Severity {
    kStructure,  // the file cannot be used as COCO (types, keys, ids, references, lengths)
    kMeaning,    // usable but wrong (keypoints outside the image, num_keypoints, area, box)
  };
  Severity severity = Severity::kStructure;
  std::string path;  // e.g. "annotations[12].keypoints[5]"
  std::string message;
};

struct ValidateOptions {
  std::filesystem::path images_dir;  // if set, every image's file must exist under it
};

// Every problem of a COCO keypoint file, in file order.
std::vector<Problem> validate_coco(const json& root, const ValidateOptions& options = {});

// Throws Error naming `source` and the first structural problem (tools need a usable file);
// problems of meaning only warn.
void require_usable(const json& root, const std::string& source);

// Index of image ids (top-level images[]) -> position; root must be usable.
std::vector<std::int64_t> image_ids(const json& root);

}  // namespace wheelpose::dataset
