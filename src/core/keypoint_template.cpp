#include "core/keypoint_template.h"

#include <cmath>
#include <nlohmann/json.hpp>
#include <set>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/parse_error.h"

namespace wheelpose {
namespace {

using nlohmann::json;

int keypoint_by_name(const KeypointTemplate& t, const json& value, const std::string& source,
                     const std::string& where) {
  if (!value.is_string()) fail(source, where, "expected a keypoint name (string)");
  const int index = t.index_of(value.get<std::string>());
  if (index < 0) fail(source, where, "unknown keypoint '" + value.get<std::string>() + "'");
  return index;
}

}  // namespace

int KeypointTemplate::index_of(std::string_view keypoint_name) const {
  for (int i = 0; i < size(); ++i) {
    if (keypoints[i].name == keypoint_name) return i;
  }
  return -1;
}

KeypointTemplate parse_keypoint_template(std::string_view json_text, const std::string& source) {
  json root;
  try {
    root = json::parse(json_text);
  } catch (const json::parse_error& e) {
    throw Error(source + ": malformed JSON: " + e.what());
  }
  if (!root.is_object()) fail(source, "top level", "expected an object");
  KeypointTemplate t;
  t.name = root.value("name", std::string());
  if (!root.contains("keypoints") || !root["keypoints"].is_array() || root["keypoints"].empty()) {
    fail(source, "keypoints", "expected a non-empty array");
  }
  std::set<std::string> seen;
  for (std::size_t i = 0; i < root["keypoints"].size(); ++i) {
    const json& k = root["keypoints"][i];
    const std::string where = "keypoints[" + std::to_string(i) + "]";
    if (!k.is_object()) fail(source, where, "expected an object {name, sigma}");
    if (!k.contains("name") || !k["name"].is_string() || k["name"].get<std::string>().empty()) {
      fail(source, where + ".name", "expected a non-empty string");
    }
    if (!k.contains("sigma") || !k["sigma"].is_number()) {
      fail(source, where + ".sigma", "expected a number");
    }
    KeypointInfo info;
    info.name = k["name"].get<std::string>();
    info.sigma = k["sigma"].get<double>();
    if (k.contains("occlusion_tolerance_m")) {
      const json& tol = k["occlusion_tolerance_m"];
      if (!tol.is_number() || !(tol.get<double>() >= 0.0)) {
        fail(source, where + ".occlusion_tolerance_m", "expected a non-negative number");
      }
      info.occlusion_tolerance_m = tol.get<double>();
    }
    if (k.contains("anchor")) {
      if (!k["anchor"].is_string()) fail(source, where + ".anchor", "expected a string");
      info.anchor = k["anchor"].get<std::string>();
    }
    // A zero sigma would divide by zero in OKS.
    if (!std::isfinite(info.sigma) || info.sigma <= 0.0) {
      fail(source, where + ".sigma", "must be a positive finite number");
    }
    if (!seen.insert(info.name).second) {
      fail(source, where + ".name", "duplicate keypoint '" + info.name + "'");
    }
    t.keypoints.push_back(std::move(info));
  }
  if (root.contains("skeleton")) {
    const json& s = root["skeleton"];
    if (!s.is_array()) fail(source, "skeleton", "expected an array of [a, b] pairs");
    for (std::size_t i = 0; i < s.size(); ++i) {
      const std::string where = "skeleton[" + std::to_string(i) + "]";
      if (!s[i].is_array() || s[i].size() != 2 || !s[i][0].is_number_integer() ||
          !s[i][1].is_number_integer()) {
        fail(source, where, "expected [a, b] with 1-based keypoint numbers");
      }
      const int a = s[i][0].get<int>() - 1;
      const int b = s[i][1].get<int>() - 1;
      if (a < 0 || a >= t.size() || b < 0 || b >= t.size()) {
        fail(source, where, "keypoint number out of range 1.." + std::to_string(t.size()));
      }
      t.skeleton.emplace_back(a, b);
    }
  }
  if (root.contains("flip_pairs")) {
    const json& f = root["flip_pairs"];
    if (!f.is_array()) fail(source, "flip_pairs", "expected an array of [name, name] pairs");
    for (std::size_t i = 0; i < f.size(); ++i) {
      const std::string where = "flip_pairs[" + std::to_string(i) + "]";
      if (!f[i].is_array() || f[i].size() != 2) fail(source, where, "expected [name, name]");
      t.flip_pairs.emplace_back(keypoint_by_name(t, f[i][0], source, where),
                                keypoint_by_name(t, f[i][1], source, where));
    }
  }
  if (root.contains("groups")) {
    const json& g = root["groups"];
    if (!g.is_array()) fail(source, "groups", "expected an array of {name, keypoints}");
    for (std::size_t i = 0; i < g.size(); ++i) {
      const std::string where = "groups[" + std::to_string(i) + "]";
      if (!g[i].is_object() || !g[i].contains("name") || !g[i]["name"].is_string() ||
          !g[i].contains("keypoints") || !g[i]["keypoints"].is_array()) {
        fail(source, where, "expected {\"name\": string, \"keypoints\": [names]}");
      }
      KeypointGroup group{g[i]["name"].get<std::string>(), {}};
      for (const json& name : g[i]["keypoints"]) {
        group.indices.push_back(keypoint_by_name(t, name, source, where + ".keypoints"));
      }
      t.groups.push_back(std::move(group));
    }
  }
  return t;
}

KeypointTemplate load_keypoint_template(const std::string& name_or_path) {
  if (name_or_path == "coco17") {
    return parse_keypoint_template(builtin_coco17_json(), "<built-in coco17 template>");
  }
  if (name_or_path == "coco17-raised-hips") {
    return parse_keypoint_template(builtin_coco17_raised_hips_json(),
                                   "<built-in coco17-raised-hips template>");
  }
  if (name_or_path == "coco17-as-annotated") {
    return parse_keypoint_template(builtin_coco17_as_annotated_json(),
                                   "<built-in coco17-as-annotated template>");
  }
  return parse_keypoint_template(read_file(name_or_path), name_or_path);
}

json coco_person_category(const KeypointTemplate& t) {
  json names = json::array(), skeleton = json::array();
  for (const auto& k : t.keypoints) names.push_back(k.name);
  for (const auto& [a, b] : t.skeleton) skeleton.push_back({a + 1, b + 1});
  return {{"id", 1},
          {"name", "person"},
          {"supercategory", "person"},
          {"keypoints", std::move(names)},
          {"skeleton", std::move(skeleton)}};
}

}  // namespace wheelpose
