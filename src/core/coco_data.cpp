#include "core/coco_data.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/parse_error.h"
#include "core/text_escape.h"

namespace wheelpose::coco {
namespace {

using nlohmann::json;

std::string entry(const std::string& array, std::size_t index) {
  return array + "[" + std::to_string(index) + "]";
}

// Integers may be written as 785 or 785.0 (Python treats both as the same dict key).
std::int64_t get_int(const json& object, const char* key, const std::string& source,
                     const std::string& where) {
  if (!object.contains(key)) fail(source, where, std::string("missing field '") + key + "'");
  const json& v = object[key];
  if (v.is_number_integer()) return v.get<std::int64_t>();
  if (v.is_number_float()) {
    const double d = v.get<double>();
    if (std::isfinite(d) && d == std::floor(d) && std::fabs(d) < 9e15) {
      return static_cast<std::int64_t>(d);
    }
  }
  fail(source, where + "." + key, "expected an integer, got " + v.dump());
}

double get_number(const json& v, const std::string& source, const std::string& where) {
  if (!v.is_number()) fail(source, where, "expected a number, got " + v.dump());
  const double d = v.get<double>();
  if (!std::isfinite(d)) fail(source, where, "not a finite number");
  return d;
}

Box get_box(const json& v, const std::string& source, const std::string& where) {
  if (!v.is_array() || v.size() != 4) fail(source, where, "expected [x, y, w, h]");
  return Box{get_number(v[0], source, where + "[0]"), get_number(v[1], source, where + "[1]"),
             get_number(v[2], source, where + "[2]"), get_number(v[3], source, where + "[3]")};
}

std::vector<double> get_keypoints(const json& v, int num_keypoints, const std::string& source,
                                  const std::string& where) {
  if (!v.is_array()) fail(source, where, "expected an array of x, y, v triples");
  if (v.size() != static_cast<std::size_t>(3 * num_keypoints)) {
    fail(source, where,
         "expected " + std::to_string(3 * num_keypoints) + " numbers (" +
             std::to_string(num_keypoints) + " keypoints x 3), got " + std::to_string(v.size()));
  }
  std::vector<double> out(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) {
    out[i] = get_number(v[i], source, where + "[" + std::to_string(i) + "]");
  }
  return out;
}

const json& get_array(const json& root, const char* key, const std::string& source) {
  if (!root.contains(key)) fail(source, "top level", std::string("missing field '") + key + "'");
  if (!root[key].is_array()) fail(source, key, "expected an array");
  return root[key];
}

}  // namespace

int CocoGroundTruth::image_position(std::int64_t image_id) const {
  const auto it = std::lower_bound(images.begin(), images.end(), image_id,
                                   [](const GtImage& a, std::int64_t id) { return a.id < id; });
  return it != images.end() && it->id == image_id ? static_cast<int>(it - images.begin()) : -1;
}

int CocoGroundTruth::category_position(std::int64_t category_id) const {
  const auto it = std::lower_bound(category_ids.begin(), category_ids.end(), category_id);
  return it != category_ids.end() && *it == category_id
             ? static_cast<int>(it - category_ids.begin())
             : -1;
}

json parse_json_file(const std::filesystem::path& path) {
  const std::string text = read_file(path);
  if (text.find_first_not_of(" \t\r\n") == std::string::npos) {
    throw Error(path.string() + ": empty file, not JSON");
  }
  try {
    return json::parse(text);
  } catch (const json::parse_error& e) {
    // e.byte is the offset; report the line too, which editors show.
    const std::size_t offset = std::min<std::size_t>(e.byte, text.size());
    const auto line = 1 + std::count(text.begin(), text.begin() + offset, '\n');
    // Show what precedes the error so the broken entry can be found (NaN is a common cause).
    const std::size_t from = offset > 40 ? offset - 40 : 0;
    std::string near = text.substr(from, offset - from);
    std::replace(near.begin(), near.end(), '\n', ' ');
    // The hint only where the failing token is one (Python's json writes NaN and Infinity).
    const std::string around = text.substr(offset > 8 ? offset - 8 : 0, 16);
    const bool looks_like_nan = around.find("NaN") != std::string::npos ||
                                around.find("Infinity") != std::string::npos ||
                                around.find("nan") != std::string::npos;
    throw Error(path.string() + ": malformed JSON at line " + std::to_string(line) + " (byte " +
                std::to_string(e.byte) +
                (near.empty() ? "" : ", after '" + escape_bytes(near) + "'") + ")" +
                (looks_like_nan ? "; note NaN/Infinity are not valid JSON" : ""));
  } catch (const json::exception& e) {
    // e.g. 1e999: a number that overflows to infinity.
    throw Error(path.string() + ": invalid JSON: " + e.what());
  }
}

CocoGroundTruth parse_coco_gt(const json& root, const std::string& source, int num_keypoints,
                              bool need_keypoints) {
  if (!root.is_object()) fail(source, "top level", "expected a COCO object, not a results list");
  CocoGroundTruth gt;
  gt.source = source;
  const json& images = get_array(root, "images", source);
  for (std::size_t i = 0; i < images.size(); ++i) {
    const std::string where = entry("images", i);
    if (!images[i].is_object()) fail(source, where, "expected an object");
    GtImage image{get_int(images[i], "id", source, where), {}};
    if (images[i].contains("file_name") && images[i]["file_name"].is_string()) {
      image.file_name = images[i]["file_name"].get<std::string>();
    }
    gt.images.push_back(std::move(image));
  }
  // COCO() indexes images by id, so a repeated id is one image.
  std::stable_sort(gt.images.begin(), gt.images.end(),
                   [](const GtImage& a, const GtImage& b) { return a.id < b.id; });
  gt.images.erase(std::unique(gt.images.begin(), gt.images.end(),
                              [](const GtImage& a, const GtImage& b) { return a.id == b.id; }),
                  gt.images.end());

  const json& categories = get_array(root, "categories", source);
  if (categories.empty()) fail(source, "categories", "no categories: nothing to evaluate");
  for (std::size_t i = 0; i < categories.size(); ++i) {
    if (!categories[i].is_object()) fail(source, entry("categories", i), "expected an object");
    gt.category_ids.push_back(get_int(categories[i], "id", source, entry("categories", i)));
  }
  std::sort(gt.category_ids.begin(), gt.category_ids.end());
  gt.category_ids.erase(std::unique(gt.category_ids.begin(), gt.category_ids.end()),
                        gt.category_ids.end());

  if (root.contains("annotations")) {
    const json& anns = get_array(root, "annotations", source);
    std::set<std::int64_t> ids;
    for (std::size_t i = 0; i < anns.size(); ++i) {
      const std::string where = entry("annotations", i);
      const json& a = anns[i];
      if (!a.is_object()) fail(source, where, "expected an object");
      GtAnnotation g;
      g.id = get_int(a, "id", source, where);
      if (!ids.insert(g.id).second) {
        fail(source, where + ".id", "duplicate annotation id " + std::to_string(g.id));
      }
      g.image_id = get_int(a, "image_id", source, where);
      g.category_id = get_int(a, "category_id", source, where);
      if (!a.contains("area")) fail(source, where, "missing field 'area'");
      g.area = get_number(a["area"], source, where + ".area");
      if (!a.contains("bbox")) fail(source, where, "missing field 'bbox'");
      g.bbox = get_box(a["bbox"], source, where + ".bbox");
      if (a.contains("iscrowd")) {
        const json& c = a["iscrowd"];
        if (c.is_boolean()) {
          g.iscrowd = c.get<bool>();
        } else if (c.is_number()) {
          g.iscrowd = c.get<double>() != 0.0;
        } else {
          fail(source, where + ".iscrowd", "expected 0/1");
        }
      }
      if (a.contains("num_keypoints")) {
        g.num_keypoints = static_cast<int>(get_int(a, "num_keypoints", source, where));
      } else if (need_keypoints) {
        fail(source, where, "missing field 'num_keypoints'");
      }
      if (a.contains("keypoints")) {
        g.keypoints = get_keypoints(a["keypoints"], num_keypoints, source, where + ".keypoints");
      } else if (need_keypoints) {
        fail(source, where, "missing field 'keypoints'");
      }
      gt.annotations.push_back(std::move(g));
    }
  }
  return gt;
}

CocoGroundTruth load_coco_gt(const std::filesystem::path& path, int num_keypoints,
                             bool need_keypoints) {
  return parse_coco_gt(parse_json_file(path), path.string(), num_keypoints, need_keypoints);
}

CocoResults parse_coco_results(const json& root, const std::string& source,
                               const CocoGroundTruth& gt, int num_keypoints) {
  if (!root.is_array()) {
    fail(source, "top level", "expected a list of results [{image_id, category_id, score, ...}]");
  }
  CocoResults res;
  res.source = source;
  res.has_keypoints = true;
  res.has_bbox = true;
  // loadRes decides from the first entry: a non-empty bbox means box results (area = w*h) even
  // when keypoints are present, as Detectron2 writes them; otherwise keypoints give the box.
  const bool bbox_branch = !root.empty() && root[0].is_object() && root[0].contains("bbox") &&
                           !(root[0]["bbox"].is_array() && root[0]["bbox"].empty());
  for (std::size_t i = 0; i < root.size(); ++i) {
    const std::string where = entry("results", i);
    const json& r = root[i];
    if (!r.is_object()) fail(source, where, "expected an object");
    Detection d;
    d.id = static_cast<std::int64_t>(i) + 1;
    d.image_id = get_int(r, "image_id", source, where);
    if (gt.image_position(d.image_id) < 0) {
      fail(source, where + ".image_id",
           "image id " + std::to_string(d.image_id) + " is not in the ground truth");
    }
    d.category_id = get_int(r, "category_id", source, where);
    if (!r.contains("score")) fail(source, where, "missing field 'score'");
    d.score = get_number(r["score"], source, where + ".score");
    if (r.contains("keypoints")) {
      d.keypoints = get_keypoints(r["keypoints"], num_keypoints, source, where + ".keypoints");
    } else {
      res.has_keypoints = false;
    }
    if (bbox_branch) {
      if (!r.contains("bbox")) fail(source, where, "missing field 'bbox' (entry 0 has one)");
      d.bbox = get_box(r["bbox"], source, where + ".bbox");
      d.area = d.bbox.w * d.bbox.h;
    } else {
      if (d.keypoints.empty()) {
        fail(source, where, "missing field 'keypoints' (needed when results have no bbox)");
      }
      double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0;
      for (std::size_t k = 0; k + 2 < d.keypoints.size(); k += 3) {
        x0 = std::min(x0, d.keypoints[k]);
        x1 = std::max(x1, d.keypoints[k]);
        y0 = std::min(y0, d.keypoints[k + 1]);
        y1 = std::max(y1, d.keypoints[k + 1]);
      }
      d.area = (x1 - x0) * (y1 - y0);
      d.bbox = Box{x0, y0, x1 - x0, y1 - y0};
    }
    res.detections.push_back(std::move(d));
  }
  return res;
}

CocoResults load_coco_results(const std::filesystem::path& path, const CocoGroundTruth& gt,
                              int num_keypoints) {
  return parse_coco_results(parse_json_file(path), path.string(), gt, num_keypoints);
}

void require_fields(const CocoResults& results, IouType type) {
  if (type != IouType::kKeypoints || results.has_keypoints) return;
  for (std::size_t i = 0; i < results.detections.size(); ++i) {
    if (results.detections[i].keypoints.empty()) {
      fail(results.source, entry("results", i),
           "missing field 'keypoints' (needed for --type keypoints)");
    }
  }
}

}  // namespace wheelpose::coco
