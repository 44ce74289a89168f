#pragma once
// Small COCO builders shared by the tests of the COCO reader and the eval layer.

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/coco_data.h"

namespace wheelpose::coco::fixtures {

using nlohmann::json;

// 17 labelled keypoints spread over a 40 x 80 box starting at (x, y); v = 2.
inline json person_keypoints(double x, double y, int visibility = 2) {
  json k = json::array();
  for (int i = 0; i < 17; ++i) {
    k.push_back(x + 2.0 * i);
    k.push_back(y + 4.0 * i);
    k.push_back(visibility);
  }
  return k;
}

inline json gt_person(long id, long image_id, double x, double y, double area) {
  return json{{"id", id},
              {"image_id", image_id},
              {"category_id", 1},
              {"area", area},
              {"bbox", {x, y, 40, 80}},
              {"iscrowd", 0},
              {"num_keypoints", 17},
              {"keypoints", person_keypoints(x, y)}};
}

inline json gt_file(const std::vector<long>& image_ids, const std::vector<json>& annotations) {
  json images = json::array();
  for (long id : image_ids)
    images.push_back({{"id", id}, {"file_name", std::to_string(id) + ".jpg"}});
  json anns = json::array();
  for (const json& a : annotations) anns.push_back(a);
  return json{
      {"images", images}, {"annotations", anns}, {"categories", {{{"id", 1}, {"name", "person"}}}}};
}

inline json kp_result(long image_id, double x, double y, double score) {
  return json{{"image_id", image_id},
              {"category_id", 1},
              {"score", score},
              {"keypoints", person_keypoints(x, y, 1)}};
}

// A JSON array from a list (brace-initialising json from one element would not make an array).
inline json json_list(const std::vector<json>& items) {
  json out = json::array();
  for (const json& item : items) out.push_back(item);
  return out;
}

inline json box_result(long image_id, double x, double y, double w, double h, double score) {
  return json{{"image_id", image_id}, {"category_id", 1}, {"score", score}, {"bbox", {x, y, w, h}}};
}

}  // namespace wheelpose::coco::fixtures
