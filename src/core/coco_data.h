#pragma once
// COCO ground truth and results, loaded and validated the way pycocotools' COCO() and
// COCO.loadRes() interpret them. Every rejection names the file, the entry index and the field.

#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace wheelpose::coco {

enum class IouType { kKeypoints, kBbox };

struct Box {
  double x = 0, y = 0, w = 0, h = 0;
};

struct GtImage {
  std::int64_t id = 0;
  std::string file_name;
};

struct GtAnnotation {
  std::int64_t id = 0;
  std::int64_t image_id = 0;
  std::int64_t category_id = 0;
  double area = 0;  // the `area` field as-is: OKS scale and area bucket
  Box bbox;
  bool iscrowd = false;
  int num_keypoints = -1;         // the field, -1 if absent
  std::vector<double> keypoints;  // x, y, v triples; empty if absent
};

struct CocoGroundTruth {
  std::string source;
  std::vector<GtImage> images;                      // sorted by id, unique
  std::vector<std::int64_t> category_ids;           // sorted, unique
  std::vector<GtAnnotation> annotations;            // file order
  int image_position(std::int64_t image_id) const;  // index into images, -1 if unknown
  int category_position(std::int64_t category_id) const;
};

struct Detection {
  std::int64_t id = 0;  // 1-based position in the results file, as loadRes assigns
  std::int64_t image_id = 0;
  std::int64_t category_id = 0;
  double score = 0;
  double area = 0;  // loadRes: bbox w*h, or keypoint extent when results carry no bbox
  Box bbox;
  std::vector<double> keypoints;  // empty if absent
};

struct CocoResults {
  std::string source;
  std::vector<Detection> detections;  // file order
  bool has_keypoints = false;         // every detection carries keypoints
  bool has_bbox = false;              // every detection has a bbox (given or from keypoints)
};

// Parses a JSON file; malformed JSON throws Error naming the file and byte offset.
nlohmann::json parse_json_file(const std::filesystem::path& path);

// `num_keypoints` = template size; GT keypoint arrays must hold 3*num_keypoints numbers.
// With `need_keypoints`, every annotation must have keypoints and num_keypoints.
CocoGroundTruth parse_coco_gt(const nlohmann::json& root, const std::string& source,
                              int num_keypoints, bool need_keypoints);
CocoGroundTruth load_coco_gt(const std::filesystem::path& path, int num_keypoints,
                             bool need_keypoints);

CocoResults parse_coco_results(const nlohmann::json& root, const std::string& source,
                               const CocoGroundTruth& gt, int num_keypoints);
CocoResults load_coco_results(const std::filesystem::path& path, const CocoGroundTruth& gt,
                              int num_keypoints);

// Throws Error naming the first detection that lacks what `type` needs.
void require_fields(const CocoResults& results, IouType type);

}  // namespace wheelpose::coco
