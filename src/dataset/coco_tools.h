#pragma once
// Whole-file COCO operations: merge, sample, split and YOLO-pose export. Inputs must be usable
// (require_usable); outputs are in the canonical form of coco_file.h.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "core/keypoint_template.h"
#include "dataset/coco_file.h"

namespace wheelpose::dataset {

struct NamedCoco {
  std::string source;  // file name, for messages
  json root;
};

// Concatenates inputs in order: images renumbered from 1 (each input's images by id), then
// annotations from 1 in (new image id, input, old id) order. Categories must agree (id, name,
// keypoint names); info, licenses and categories come from the first input. Two inputs that use
// the same file_name are an error.
// With replace_by_filename, the first input is the base: each later input's images must exist in
// the base by file_name, and their annotations replace the base image's (later inputs win).
json merge_coco(const std::vector<NamedCoco>& inputs, bool replace_by_filename);

// N images (and their annotations), ids kept. Random: a seeded draw without replacement.
// Even: positions round(i * (n - 1) / (N - 1)) of the images sorted by id, i = 0..N-1, so the
// first and last image are always included (N = 1 takes the first).
json sample_coco(const json& root, const std::string& source, std::int64_t n, bool even,
                 std::uint64_t seed);

enum class GroupBy { kImage, kMotion };

struct SplitPart {
  std::string name;
  json root;
};

// Splits images into parts with the given ratios (normalised). With kMotion, images sharing a
// `motion_id` (on the image or on any of its annotations) stay in one part; images without one
// are groups of their own. Groups are shuffled with the seed, then each goes to the part that
// is furthest below its target image count (ties: the earlier part).
std::vector<SplitPart> split_coco(const json& root, const std::vector<double>& ratios,
                                  const std::vector<std::string>& names, GroupBy group_by,
                                  std::uint64_t seed);

// Ultralytics YOLO-pose labels: out/labels/<file stem>.txt per image (empty when it has no
// person) with lines "class cx cy w h x1 y1 v1 ..." normalised by the image size, and
// out/data.yaml (kpt_shape, flip_idx from the template's flip pairs, names). Crowd regions and
// empty boxes are skipped. Returns the number of label lines.
std::size_t export_yolo_pose(const json& root, const std::string& source,
                             const KeypointTemplate& keypoint_template,
                             const std::filesystem::path& out_dir);

}  // namespace wheelpose::dataset
