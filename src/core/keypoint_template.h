#pragma once
// The dataset's keypoint vocabulary, shared by every layer that writes or reads labels
// (generate, dataset, eval, learn). A keypoint template names the keypoints of a pose format and
// gives each its COCO OKS sigma, the drawing skeleton, left/right flip pairs and named groups used
// by the per-keypoint report. File format (JSON): {"name", "keypoints": [{"name", "sigma", ...}],
// "skeleton": [[a, b], ...] (1-based, as in COCO categories), "flip_pairs": [[name, name]],
// "groups": [{"name", "keypoints": [names]}]}. Unknown per-keypoint fields are allowed so other
// tools can extend it.

#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace wheelpose {

struct KeypointInfo {
  std::string name;
  double sigma = 0.0;
  // Used by scene generation (optional here): how far in front of the point, in metres, the
  // first surface may be before the point counts as occluded; where on the body it sits.
  double occlusion_tolerance_m = 0.0;
  std::string anchor;
};

struct KeypointGroup {
  std::string name;
  std::vector<int> indices;  // 0-based keypoint indices
};

struct KeypointTemplate {
  std::string name;
  std::vector<KeypointInfo> keypoints;
  std::vector<std::pair<int, int>> skeleton;    // 0-based
  std::vector<std::pair<int, int>> flip_pairs;  // 0-based
  std::vector<KeypointGroup> groups;

  int size() const { return static_cast<int>(keypoints.size()); }
  int index_of(std::string_view keypoint_name) const;  // -1 if absent
};

// Parses template JSON text; `source` names it in error messages.
KeypointTemplate parse_keypoint_template(std::string_view json_text, const std::string& source);

// "coco17", "coco17-raised-hips" and "coco17-as-annotated" select the built-in templates
// (data/keypoints/); anything else is read as a file path.
KeypointTemplate load_keypoint_template(const std::string& name_or_path);

// The texts of data/keypoints/coco17.json, coco17-raised-hips.json and
// coco17-as-annotated.json, compiled in.
std::string_view builtin_coco17_json();
std::string_view builtin_coco17_raised_hips_json();
std::string_view builtin_coco17_as_annotated_json();

// The COCO category of people labelled with this template: id 1, "person", its keypoint names
// and its skeleton (1-based), as every COCO file the toolkit writes carries it.
nlohmann::json coco_person_category(const KeypointTemplate& t);

}  // namespace wheelpose
