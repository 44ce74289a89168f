#include "eval/realism.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <unordered_map>

#include "core/error.h"
#include "eval/oks_iou.h"

namespace wheelpose::eval {
namespace {

using nlohmann::json;

// Fields that identify or measure a person or image rather than describe a drawn choice.
const std::set<std::string>& structural_keys() {
  static const std::set<std::string> keys = {"id",
                                             "image_id",
                                             "category_id",
                                             "bbox",
                                             "area",
                                             "keypoints",
                                             "num_keypoints",
                                             "iscrowd",
                                             "segmentation",
                                             "keypoints_3d",
                                             "bbox_3d",
                                             "bbox_amodal",
                                             "instance_id",
                                             "pool_slot",
                                             "file_name",
                                             "frame",
                                             "seed",
                                             "width",
                                             "height",
                                             "coco_url",
                                             "flickr_url",
                                             "date_captured",
                                             "camera.intrinsics",
                                             "camera.extrinsics",
                                             "motion_time",
                                             "yolo_class"};
  return keys;
}

// One person's attribute values: strings (and booleans) by key, numbers by key.
struct Attributes {
  std::vector<std::pair<std::string, std::string>> labels;
  std::vector<std::pair<std::string, double>> numbers;
};

void collect(const json& value, const std::string& key, Attributes& out) {
  if (structural_keys().contains(key)) return;
  if (value.is_object()) {
    for (const auto& [name, child] : value.items()) {
      collect(child, key.empty() ? name : key + "." + name, out);
    }
  } else if (value.is_string()) {
    out.labels.emplace_back(key, value.get<std::string>());
  } else if (value.is_boolean()) {
    out.labels.emplace_back(key, value.get<bool>() ? "true" : "false");
  } else if (value.is_number()) {
    out.numbers.emplace_back(key, value.get<double>());
  } else if (value.is_array()) {
    // A list of names (assets worn) counts the person under each; numeric lists are geometry.
    for (const json& element : value) {
      if (element.is_string()) out.labels.emplace_back(key, element.get<std::string>());
    }
  }
}

std::string number_text(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", v);
  return text;
}

struct Judged {
  Attributes attributes;
  bool found = false;
  double oks = 0;
};

// Numeric attributes split at their quantiles; keys with one value say nothing and are left out.
void add_numeric_groups(const std::vector<Judged>& people, int buckets,
                        std::vector<RealismGroup>& groups) {
  std::map<std::string, std::vector<std::pair<double, const Judged*>>> by_key;
  for (const Judged& p : people) {
    for (const auto& [key, value] : p.attributes.numbers) by_key[key].emplace_back(value, &p);
  }
  for (auto& [key, values] : by_key) {
    std::sort(values.begin(), values.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<double> edges;  // lower edges of the buckets
    for (int b = 0; b < buckets; ++b) {
      const double edge = values[values.size() * b / buckets].first;
      if (edges.empty() || edge > edges.back()) edges.push_back(edge);
    }
    if (edges.size() < 2) continue;
    std::vector<RealismGroup> key_groups(edges.size());
    for (std::size_t b = 0; b < edges.size(); ++b) {
      key_groups[b].key = key;
      key_groups[b].bucket =
          b + 1 < edges.size()
              ? "[" + number_text(edges[b]) + ", " + number_text(edges[b + 1]) + ")"
              : "[" + number_text(edges[b]) + ", " + number_text(values.back().first) + "]";
    }
    for (const auto& [value, person] : values) {
      const std::size_t b =
          static_cast<std::size_t>(std::upper_bound(edges.begin(), edges.end(), value) -
                                   edges.begin()) -
          1;
      key_groups[b].people += 1;
      key_groups[b].found += person->found;
      key_groups[b].oks_sum += person->oks;
    }
    groups.insert(groups.end(), key_groups.begin(), key_groups.end());
  }
}

// Keypoints with v > 0 (labelled) or v == 2 (labelled and visible).
int count_keypoints(const coco::GtAnnotation& person, bool visible_only) {
  int count = 0;
  for (std::size_t k = 2; k < person.keypoints.size(); k += 3) {
    count += visible_only ? person.keypoints[k] == 2 : person.keypoints[k] > 0;
  }
  return count;
}
int labelled_keypoints(const coco::GtAnnotation& person) { return count_keypoints(person, false); }

// The template's nose and eyes (those it has); empty when it has none of them.
std::vector<int> face_keypoints(const KeypointTemplate& keypoint_template) {
  std::vector<int> face;
  for (const char* name : {"nose", "left_eye", "right_eye"}) {
    if (const int k = keypoint_template.index_of(name); k >= 0) face.push_back(k);
  }
  return face;
}

// Whether any of `face` is labelled visible: a person seen from behind shows neither nose nor eyes.
bool face_visible(const coco::GtAnnotation& person, const std::vector<int>& face) {
  return std::any_of(face.begin(), face.end(), [&](int k) {
    const std::size_t v = 3 * static_cast<std::size_t>(k) + 2;
    return v < person.keypoints.size() && person.keypoints[v] == 2;
  });
}

// Whether a box touches the border of its image (1 px of slack for rounded labels).
bool cut_by_frame(const coco::Box& box, const ImageSize& image) {
  return box.x <= 1 || box.y <= 1 || box.x + box.w >= image.width - 1 ||
         box.y + box.h >= image.height - 1;
}

enum class LeftOut { kNo, kCrowd, kTooSmall, kTooFewKeypoints, kTooFewVisible, kCutByFrame };

LeftOut why_left_out(const coco::GtAnnotation& person, const RealismOptions& options,
                     const ImageSizes& sizes) {
  if (person.iscrowd) return LeftOut::kCrowd;
  if (person.bbox.h < options.min_height_px) return LeftOut::kTooSmall;
  if (!options.boxes) {
    if (labelled_keypoints(person) < options.min_keypoints) return LeftOut::kTooFewKeypoints;
    if (count_keypoints(person, true) < options.min_visible_keypoints) {
      return LeftOut::kTooFewVisible;
    }
  }
  if (options.whole_in_frame) {
    const auto it = sizes.find(person.image_id);
    if (it == sizes.end() || it->second.width <= 0 || it->second.height <= 0) {
      throw Error("image " + std::to_string(person.image_id) +
                  ": no width and height, which judging only people whole in the frame needs");
    }
    if (cut_by_frame(person.bbox, it->second)) return LeftOut::kCutByFrame;
  }
  return LeftOut::kNo;
}

}  // namespace

ImageSizes image_sizes(const json& root) {
  ImageSizes sizes;
  for (const json& image : root.at("images")) {
    sizes[image.at("id").get<std::int64_t>()] = {image.value("width", 0.0),
                                                 image.value("height", 0.0)};
  }
  return sizes;
}

bool realism_judges(const coco::GtAnnotation& person, const RealismOptions& options,
                    const ImageSizes& sizes) {
  return why_left_out(person, options, sizes) == LeftOut::kNo;
}

RealismReport measure_realism(const json& root, const coco::CocoGroundTruth& gt,
                              const coco::CocoResults& results,
                              const KeypointTemplate& keypoint_template,
                              const RealismOptions& options) {
  if (!options.boxes && !results.detections.empty() && !results.has_keypoints) {
    throw Error(results.source +
                ": the detections carry no keypoints; realism needs a pose model (or --boxes)");
  }
  const std::vector<double> vars = oks_vars(keypoint_template);
  const std::vector<int> face = face_keypoints(keypoint_template);
  const ImageSizes sizes = image_sizes(root);
  std::unordered_map<std::int64_t, std::vector<const coco::Detection*>> detections_of;
  for (const coco::Detection& d : results.detections) detections_of[d.image_id].push_back(&d);
  std::unordered_map<std::int64_t, const json*> image_json;
  for (const json& image : root.at("images"))
    image_json[image.at("id").get<std::int64_t>()] = &image;

  RealismReport report;
  report.boxes = options.boxes;
  report.overall.key = report.overall.bucket = "all";
  std::vector<Judged> people;
  const json& annotations = root.at("annotations");
  for (std::size_t i = 0; i < gt.annotations.size(); ++i) {
    const coco::GtAnnotation& person = gt.annotations[i];
    switch (why_left_out(person, options, sizes)) {
      case LeftOut::kNo:
        break;
      case LeftOut::kCrowd:
        ++report.crowd;
        continue;
      case LeftOut::kTooSmall:
        ++report.too_small;
        continue;
      case LeftOut::kTooFewKeypoints:
        ++report.too_few_keypoints;
        continue;
      case LeftOut::kTooFewVisible:
        ++report.too_few_visible;
        continue;
      case LeftOut::kCutByFrame:
        ++report.cut_by_frame;
        continue;
    }
    Judged judged;
    for (const coco::Detection* d : detections_of[person.image_id]) {
      if (d->category_id != person.category_id) continue;
      const double closeness = options.boxes ? bbox_iou(d->bbox, person.bbox, false)
                                             : compute_oks(person, d->keypoints, vars);
      judged.oks = std::max(judged.oks, closeness);
    }
    judged.found = judged.oks >= (options.boxes ? options.found_iou : options.found_oks);
    collect(annotations.at(i), "", judged.attributes);
    if (const auto it = image_json.find(person.image_id); it != image_json.end()) {
      collect(*it->second, "", judged.attributes);
    }
    judged.attributes.numbers.emplace_back("height_px", person.bbox.h);
    // How much of the person shows: a renderer labels every hidden joint, a human annotator
    // only what they can place, so compare sets at equal visibility.
    judged.attributes.numbers.emplace_back("visible_keypoints", count_keypoints(person, true));
    // A person labelled by box only has no face to show or hide.
    if (!face.empty() && labelled_keypoints(person) > 0) {
      judged.attributes.labels.emplace_back("face_visible",
                                            face_visible(person, face) ? "true" : "false");
    }
    report.overall.people += 1;
    report.overall.found += judged.found;
    report.overall.oks_sum += judged.oks;
    people.push_back(std::move(judged));
  }

  std::map<std::pair<std::string, std::string>, RealismGroup> labelled_groups;
  for (const Judged& p : people) {
    std::set<std::pair<std::string, std::string>> seen;  // a person counts once per value
    for (const auto& label : p.attributes.labels) {
      if (!seen.insert(label).second) continue;
      RealismGroup& g = labelled_groups[label];
      g.key = label.first;
      g.bucket = label.second;
      g.people += 1;
      g.found += p.found;
      g.oks_sum += p.oks;
    }
  }
  for (auto& [label, group] : labelled_groups) report.groups.push_back(group);
  add_numeric_groups(people, options.numeric_buckets, report.groups);
  std::stable_sort(report.groups.begin(), report.groups.end(),
                   [](const RealismGroup& a, const RealismGroup& b) { return a.key < b.key; });
  return report;
}

std::string realism_markdown(const RealismReport& report, const std::string& title) {
  const auto row = [](const RealismGroup& g) {
    char text[256];
    std::snprintf(text, sizeof text, "| %s | %d | %.1f %% | %.3f |\n", g.bucket.c_str(), g.people,
                  100.0 * g.found_share(), g.mean_oks());
    return std::string(text);
  };
  const std::string columns = std::string("| judged | found | ") +
                              (report.boxes ? "mean box IoU" : "mean OKS") +
                              " |\n|---|---|---|---|\n";
  std::string md = "# Realism: " + title + "\n\n";
  if (report.boxes) md += "Judged by box: found where the model's best box has IoU >= 0.5.\n\n";
  md += "People judged: " + std::to_string(report.overall.people) +
        " (left out: " + std::to_string(report.too_small) + " too small, " +
        (report.boxes
             ? std::string()
             : std::to_string(report.too_few_keypoints) + " with too few labelled keypoints, ") +
        (report.too_few_visible > 0
             ? std::to_string(report.too_few_visible) + " with too few visible, "
             : std::string()) +
        (report.cut_by_frame > 0 ? std::to_string(report.cut_by_frame) + " cut by the frame, "
                                 : std::string()) +
        std::to_string(report.crowd) + " crowd regions).\n\n";
  md += "| people " + columns + row(report.overall);
  std::string key;
  for (const RealismGroup& g : report.groups) {
    if (g.key != key) {
      key = g.key;
      md += "\n## " + key + "\n\n| value " + columns;
    }
    md += row(g);
  }
  return md;
}

json realism_json(const RealismReport& report, const RealismOptions& options) {
  const char* mean_key = report.boxes ? "mean_iou" : "mean_oks";
  const auto group_json = [mean_key](const RealismGroup& g) {
    return json{{"key", g.key},
                {"value", g.bucket},
                {"people", g.people},
                {"found", g.found},
                {"found_share", g.found_share()},
                {mean_key, g.mean_oks()}};
  };
  json groups = json::array();
  for (const RealismGroup& g : report.groups) groups.push_back(group_json(g));
  return {{"options",
           {{"min_height_px", options.min_height_px},
            {"min_keypoints", options.min_keypoints},
            {"min_visible_keypoints", options.min_visible_keypoints},
            {"found_oks", options.found_oks},
            {"boxes", options.boxes},
            {"found_iou", options.found_iou},
            {"whole_in_frame", options.whole_in_frame}}},
          {"overall", group_json(report.overall)},
          {"left_out",
           {{"too_small", report.too_small},
            {"too_few_keypoints", report.too_few_keypoints},
            {"too_few_visible", report.too_few_visible},
            {"cut_by_frame", report.cut_by_frame},
            {"crowd", report.crowd}}},
          {"groups", std::move(groups)}};
}

}  // namespace wheelpose::eval
