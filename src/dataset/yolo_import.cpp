#include "dataset/yolo_import.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <system_error>
#include <vector>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/image_files.h"
#include "core/image_read.h"
#include "core/text_escape.h"

namespace wheelpose::dataset {
namespace {

namespace fs = std::filesystem;

const char* role_name(YoloRole role) {
  switch (role) {
    case YoloRole::kPerson:
      return "person";
    case YoloRole::kCrowd:
      return "crowd";
    case YoloRole::kDrop:
      return "drop";
  }
  return "?";
}

std::string classes_text(const std::map<int, YoloRole>& classes) {
  std::string text;
  for (const auto& [id, role] : classes) {
    text += (text.empty() ? "" : ",") + std::to_string(id) + "=" + role_name(role);
  }
  return text;
}

std::vector<std::string> words(const std::string& line) {
  std::vector<std::string> out;
  std::istringstream in(line);
  for (std::string w; in >> w;) out.push_back(w);
  return out;
}

double number(const std::string& word, const std::string& where) {
  double v = 0;
  const auto [end, ec] = std::from_chars(word.data(), word.data() + word.size(), v);
  if (ec != std::errc() || end != word.data() + word.size() || !std::isfinite(v)) {
    throw Error(where + ": '" + escape_bytes(word) + "' is not a number");
  }
  return v;
}

struct ImageSize {
  int width = 0, height = 0;
};

ImageSize image_size(const fs::path& path) {
  const cv::Mat image = read_image(path, cv::IMREAD_UNCHANGED);
  return {image.cols, image.rows};
}

// One label file's objects as COCO annotations (ids and image id filled in by the caller).
std::vector<json> read_labels(const fs::path& label_file, ImageSize size,
                              const std::map<int, YoloRole>& classes, int keypoint_count) {
  std::vector<json> annotations;
  std::string text = read_file(label_file);
  // A byte-order mark (some Windows editors write one) is not part of the first value.
  if (text.starts_with("\xEF\xBB\xBF")) text.erase(0, 3);
  std::istringstream in(text);
  int line_number = 0;
  for (std::string line; std::getline(in, line);) {
    ++line_number;
    const std::string where = label_file.string() + ":" + std::to_string(line_number);
    const std::vector<std::string> w = words(line);
    if (w.empty()) continue;
    const std::size_t n = w.size();
    const std::size_t k = static_cast<std::size_t>(keypoint_count);
    if (n != 5 && n != 5 + 2 * k && n != 5 + 3 * k) {
      throw Error(where + ": expected 5 values (class cx cy w h), or 5 + " + std::to_string(2 * k) +
                  " or 5 + " + std::to_string(3 * k) + " with keypoints; got " + std::to_string(n));
    }
    int class_value = -1;
    const auto [class_end, class_ec] =
        std::from_chars(w[0].data(), w[0].data() + w[0].size(), class_value);
    if (class_ec != std::errc() || class_end != w[0].data() + w[0].size()) {
      throw Error(where + ": class '" + escape_bytes(w[0]) + "' is not a whole number");
    }
    const auto class_it = classes.find(class_value);
    if (class_it == classes.end()) {
      throw Error(where + ": class " + w[0] + " is not in the class mapping (" +
                  classes_text(classes) + ")");
    }
    if (class_it->second == YoloRole::kDrop) continue;
    std::vector<double> v(n);
    for (std::size_t i = 1; i < n; ++i) v[i] = number(w[i], where);
    for (std::size_t i = 1; i < 5; ++i) {
      if (v[i] < 0 || v[i] > 1) {
        throw Error(where + ": value " + std::to_string(i + 1) + " (" + w[i] +
                    ") is outside [0, 1]");
      }
    }
    if (v[3] <= 0 || v[4] <= 0) throw Error(where + ": the box is empty (w or h is 0)");
    const double x0 = std::clamp(v[1] - v[3] / 2, 0.0, 1.0) * size.width;
    const double y0 = std::clamp(v[2] - v[4] / 2, 0.0, 1.0) * size.height;
    const double x1 = std::clamp(v[1] + v[3] / 2, 0.0, 1.0) * size.width;
    const double y1 = std::clamp(v[2] + v[4] / 2, 0.0, 1.0) * size.height;
    if (!(x1 - x0 > 0 && y1 - y0 > 0 && (x1 - x0) * (y1 - y0) > 0)) {
      throw Error(where + ": the box has no area in the " + std::to_string(size.width) + "x" +
                  std::to_string(size.height) + " image (w " + w[3] + ", h " + w[4] + ")");
    }

    json keypoints = json::array();
    int labelled = 0;
    const std::size_t stride = n == 5 + 3 * k ? 3 : 2;
    for (std::size_t j = 0; j < k; ++j) {
      double x = 0, y = 0, visibility = 0;
      if (n > 5) {
        x = v[5 + stride * j], y = v[5 + stride * j + 1];
        visibility = stride == 3 ? v[5 + stride * j + 2] : (x != 0 || y != 0 ? 2 : 0);
        if (x < 0 || x > 1 || y < 0 || y > 1) {
          throw Error(where + ": keypoint " + std::to_string(j + 1) + " is outside [0, 1]");
        }
        if (visibility != 0 && visibility != 1 && visibility != 2) {
          throw Error(where + ": keypoint " + std::to_string(j + 1) +
                      " visibility must be 0, 1 or 2");
        }
      }
      const bool labelled_point = visibility > 0;
      labelled += labelled_point;
      keypoints.push_back(labelled_point ? x * size.width : 0.0);
      keypoints.push_back(labelled_point ? y * size.height : 0.0);
      keypoints.push_back(static_cast<int>(visibility));
    }
    annotations.push_back({{"category_id", 1},
                           {"bbox", {x0, y0, x1 - x0, y1 - y0}},
                           {"area", (x1 - x0) * (y1 - y0)},
                           {"iscrowd", class_it->second == YoloRole::kCrowd ? 1 : 0},
                           {"num_keypoints", labelled},
                           {"keypoints", std::move(keypoints)},
                           {"yolo_class", class_value}});
  }
  return annotations;
}

}  // namespace

std::map<int, YoloRole> parse_yolo_classes(const std::string& text) {
  std::map<int, YoloRole> classes;
  if (!text.empty() && text.back() == ',') {
    throw Error("--classes: '" + escape_bytes(text) +
                "' has an empty item (expected e.g. 1=person,0=crowd)");
  }
  std::istringstream in(text);
  for (std::string item; std::getline(in, item, ',');) {
    const std::size_t eq = item.find('=');
    int id = -1;
    const char* first = item.data();
    const char* last = item.data() + (eq == std::string::npos ? 0 : eq);
    const auto [end, ec] = std::from_chars(first, last, id);
    const std::string role = eq == std::string::npos ? "" : item.substr(eq + 1);
    if (eq == std::string::npos || ec != std::errc() || end != last || id < 0 ||
        (role != "person" && role != "crowd" && role != "drop")) {
      throw Error("--classes: '" + escape_bytes(item) +
                  "' is not CLASS=ROLE (CLASS a number, ROLE person, crowd or drop)");
    }
    if (!classes
             .emplace(id, role == "person"  ? YoloRole::kPerson
                          : role == "crowd" ? YoloRole::kCrowd
                                            : YoloRole::kDrop)
             .second) {
      throw Error("--classes: class " + std::to_string(id) + " is mapped twice");
    }
  }
  if (classes.empty()) throw Error("--classes: empty (expected e.g. 1=person,0=crowd)");
  return classes;
}

json import_yolo(const YoloImportOptions& o, const KeypointTemplate& keypoint_template) {
  const fs::path labels_dir = o.labels_dir.empty() ? o.images_dir : o.labels_dir;
  const std::vector<fs::path> images = image_files_in(o.images_dir);
  // The same rule as predict: a folder with nothing to read is a mistake, not an empty dataset.
  if (images.empty()) {
    throw Error(o.images_dir.string() + ": no images (.jpg, .jpeg, .png, .bmp) to import");
  }
  for (const fs::path& image : images) {
    const std::string name = image.filename().string();
    if (!is_valid_utf8(name)) {
      throw Error(o.images_dir.string() + ": image name '" + escape_bytes(name) +
                  "' is not UTF-8, so a COCO file (JSON text) cannot name it; rename it");
    }
  }
  std::map<std::string, fs::path> image_by_stem;
  for (const fs::path& image : images) {
    const auto [it, inserted] = image_by_stem.emplace(image.stem().string(), image);
    if (!inserted) {
      throw Error(image.string() + ": the same label name as " + it->second.string() + " (" +
                  image.stem().string() + ".txt)");
    }
  }
  std::error_code ec;
  if (!fs::is_directory(labels_dir, ec)) throw Error(labels_dir.string() + ": not a directory");
  std::vector<fs::path> label_files;
  for (const auto& entry : fs::directory_iterator(labels_dir)) {
    if (entry.is_regular_file() && entry.path().extension() == ".txt") {
      label_files.push_back(entry.path());
    }
  }
  std::sort(label_files.begin(), label_files.end());
  for (const fs::path& label : label_files) {
    if (!image_by_stem.contains(label.stem().string())) {
      throw Error(label.string() + ": no image " + label.stem().string() +
                  ".{jpg,jpeg,png,bmp} in " + o.images_dir.string());
    }
  }

  json image_list = json::array(), annotations = json::array();
  std::int64_t image_id = 0, annotation_id = 0;
  for (const fs::path& image : images) {
    const ImageSize size = image_size(image);
    image_list.push_back({{"id", ++image_id},
                          {"file_name", image.filename().string()},
                          {"width", size.width},
                          {"height", size.height}});
    const fs::path label = labels_dir / (image.stem().string() + ".txt");
    if (!fs::exists(label, ec)) continue;
    for (json& a : read_labels(label, size, o.classes, keypoint_template.size())) {
      a["id"] = ++annotation_id;
      a["image_id"] = image_id;
      annotations.push_back(std::move(a));
    }
  }
  return {{"info",
           {{"description",
             o.description.empty() ? "YOLO labels of " + o.images_dir.string() : o.description},
            {"yolo_classes", classes_text(o.classes)}}},
          {"images", std::move(image_list)},
          {"annotations", std::move(annotations)},
          {"categories", json::array({coco_person_category(keypoint_template)})}};
}

}  // namespace wheelpose::dataset
