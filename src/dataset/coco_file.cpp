#include "dataset/coco_file.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <unordered_map>
#include <unordered_set>

#include "core/atomic_file.h"
#include "core/coco_data.h"
#include "core/error.h"

namespace wheelpose::dataset {
namespace {

using Severity = Problem::Severity;

std::string at(const std::string& array, std::size_t index) {
  return array + "[" + std::to_string(index) + "]";
}

std::string number_text(double v) {
  // Integral values as integers (COCO files write 250 and 250.0 alike); others shortest exact.
  if (std::fabs(v) < 1e15 && v == std::floor(v)) return std::to_string(static_cast<long long>(v));
  return json(v).dump();
}

// Sort key of an element by one integer field; elements without it sort last, stably.
std::int64_t key_of(const json& element, const char* key) {
  if (!element.is_object()) return INT64_MAX;
  const auto it = element.find(key);
  if (it == element.end()) return INT64_MAX;
  return as_integer(*it).value_or(INT64_MAX);
}

class Validator {
 public:
  explicit Validator(const ValidateOptions& options) : options_(options) {}

  std::vector<Problem> run(const json& root) {
    if (!root.is_object()) {
      add(Severity::kStructure, "(top level)",
          "expected a COCO object {images, annotations, categories}");
      return std::move(problems_);
    }
    const json* categories = top_array(root, "categories");
    const json* images = top_array(root, "images");
    const json* annotations = top_array(root, "annotations");
    if (categories) check_categories(*categories);
    if (images) check_images(*images);
    if (annotations) check_annotations(*annotations, images != nullptr, categories != nullptr);
    return std::move(problems_);
  }

 private:
  struct ImageInfo {
    double width = 0, height = 0;  // 0 if unknown
  };
  struct CategoryInfo {
    int num_keypoints = 0;
    std::vector<std::string> names;
  };

  void add(Severity s, std::string path, std::string message) {
    problems_.push_back(Problem{s, std::move(path), std::move(message)});
  }

  const json* top_array(const json& root, const char* key) {
    const auto it = root.find(key);
    if (it == root.end()) {
      add(Severity::kStructure, key, "missing");
      return nullptr;
    }
    if (!it->is_array()) {
      add(Severity::kStructure, key, "expected an array");
      return nullptr;
    }
    return &*it;
  }

  // The integer field `key` of `object`, or nullopt after reporting what is wrong.
  std::optional<std::int64_t> integer(const json& object, const char* key, const std::string& path,
                                      bool required = true) {
    const auto it = object.find(key);
    if (it == object.end()) {
      if (required) add(Severity::kStructure, path + "." + key, "missing");
      return std::nullopt;
    }
    auto v = as_integer(*it);
    if (!v) add(Severity::kStructure, path + "." + key, "expected an integer, got " + it->dump());
    return v;
  }

  std::optional<double> number(const json& v, const std::string& path) {
    if (!v.is_number()) {
      add(Severity::kStructure, path, "expected a number, got " + v.dump());
      return std::nullopt;
    }
    const double d = v.get<double>();
    if (!std::isfinite(d)) {
      add(Severity::kStructure, path, "not a finite number");
      return std::nullopt;
    }
    return d;
  }

  // An id field: integer >= 1 and unique within `seen`.
  std::optional<std::int64_t> id(const json& object, const std::string& path,
                                 std::unordered_map<std::int64_t, std::size_t>& seen,
                                 const std::string& array, std::size_t index) {
    auto v = integer(object, "id", path);
    if (!v) return std::nullopt;
    if (*v < 1) {
      add(Severity::kStructure, path + ".id", "must be >= 1, got " + std::to_string(*v));
      return std::nullopt;
    }
    const auto [it, inserted] = seen.emplace(*v, index);
    if (!inserted) {
      add(Severity::kStructure, path + ".id",
          "duplicate id " + std::to_string(*v) + " (first at " + at(array, it->second) + ")");
      return std::nullopt;
    }
    return v;
  }

  void check_categories(const json& categories) {
    std::unordered_map<std::int64_t, std::size_t> seen;
    for (std::size_t i = 0; i < categories.size(); ++i) {
      const json& c = categories[i];
      const std::string path = at("categories", i);
      if (!c.is_object()) {
        add(Severity::kStructure, path, "expected an object");
        continue;
      }
      const auto cid = id(c, path, seen, "categories", i);
      if (!c.contains("name") || !c["name"].is_string()) {
        add(Severity::kStructure, path + ".name", "missing or not a string");
      }
      CategoryInfo info;
      if (c.contains("keypoints")) {
        const json& k = c["keypoints"];
        if (!k.is_array()) {
          add(Severity::kStructure, path + ".keypoints", "expected an array of names");
        } else {
          for (std::size_t j = 0; j < k.size(); ++j) {
            if (!k[j].is_string()) {
              add(Severity::kStructure, at(path + ".keypoints", j), "expected a name (string)");
              info.names.push_back("?");
            } else {
              info.names.push_back(k[j].get<std::string>());
            }
          }
          info.num_keypoints = static_cast<int>(k.size());
        }
      }
      if (c.contains("skeleton"))
        check_skeleton(c["skeleton"], path + ".skeleton", info.num_keypoints);
      if (cid) categories_[*cid] = std::move(info);
    }
  }

  void check_skeleton(const json& s, const std::string& path, int num_keypoints) {
    if (!s.is_array()) {
      add(Severity::kStructure, path, "expected an array of [a, b] pairs");
      return;
    }
    for (std::size_t j = 0; j < s.size(); ++j) {
      const json& pair = s[j];
      if (!pair.is_array() || pair.size() != 2 || !as_integer(pair[0]) || !as_integer(pair[1])) {
        add(Severity::kStructure, at(path, j), "expected a pair of 1-based keypoint indices");
        continue;
      }
      for (int e = 0; e < 2; ++e) {
        const std::int64_t k = *as_integer(pair[e]);
        if (k < 1 || k > num_keypoints) {
          add(Severity::kStructure, at(path, j),
              "keypoint index " + std::to_string(k) + " is outside 1.." +
                  std::to_string(num_keypoints));
        }
      }
    }
  }

  void check_images(const json& images) {
    std::unordered_map<std::int64_t, std::size_t> seen;
    std::unordered_map<std::string, std::size_t> names;
    for (std::size_t i = 0; i < images.size(); ++i) {
      const json& im = images[i];
      const std::string path = at("images", i);
      if (!im.is_object()) {
        add(Severity::kStructure, path, "expected an object");
        continue;
      }
      const auto iid = id(im, path, seen, "images", i);
      ImageInfo info;
      for (const char* key : {"width", "height"}) {
        const auto v = integer(im, key, path);
        if (v && *v < 1) {
          add(Severity::kStructure, path + "." + key, "must be >= 1, got " + std::to_string(*v));
        } else if (v) {
          (key[0] == 'w' ? info.width : info.height) = static_cast<double>(*v);
        }
      }
      const auto name = im.find("file_name");
      if (name == im.end() || !name->is_string() || name->get<std::string>().empty()) {
        add(Severity::kStructure, path + ".file_name", "missing or not a non-empty string");
      } else {
        const std::string file = name->get<std::string>();
        const auto [it, inserted] = names.emplace(file, i);
        if (!inserted) {
          add(Severity::kMeaning, path + ".file_name",
              "'" + file + "' also used by " + at("images", it->second));
        }
        if (!options_.images_dir.empty()) {
          std::error_code ec;
          if (!std::filesystem::is_regular_file(options_.images_dir / file, ec)) {
            add(Severity::kMeaning, path + ".file_name",
                "no file " + (options_.images_dir / file).string());
          }
        }
      }
      // Without both sizes the geometry checks are skipped (the missing size is reported).
      if (info.width == 0 || info.height == 0) info = ImageInfo{};
      if (iid) images_[*iid] = info;
    }
  }

  void check_annotations(const json& annotations, bool have_images, bool have_categories) {
    std::unordered_map<std::int64_t, std::size_t> seen;
    for (std::size_t i = 0; i < annotations.size(); ++i) {
      const json& a = annotations[i];
      const std::string path = at("annotations", i);
      if (!a.is_object()) {
        add(Severity::kStructure, path, "expected an object");
        continue;
      }
      id(a, path, seen, "annotations", i);
      const ImageInfo* image = nullptr;
      if (const auto iid = integer(a, "image_id", path); iid && have_images) {
        const auto it = images_.find(*iid);
        if (it == images_.end()) {
          add(Severity::kStructure, path + ".image_id", "no image has id " + std::to_string(*iid));
        } else {
          image = it->second.width > 0 ? &it->second : nullptr;
        }
      }
      const CategoryInfo* category = nullptr;
      if (const auto cid = integer(a, "category_id", path); cid && have_categories) {
        const auto it = categories_.find(*cid);
        if (it == categories_.end()) {
          add(Severity::kStructure, path + ".category_id",
              "no category has id " + std::to_string(*cid));
        } else {
          category = &it->second;
        }
      }
      if (const auto crowd = integer(a, "iscrowd", path); crowd && *crowd != 0 && *crowd != 1) {
        add(Severity::kStructure, path + ".iscrowd",
            "must be 0 or 1, got " + std::to_string(*crowd));
      }
      if (!a.contains("area")) {
        add(Severity::kStructure, path + ".area", "missing");
      } else if (const auto area = number(a["area"], path + ".area"); area && *area <= 0) {
        add(Severity::kMeaning, path + ".area", "must be positive, got " + number_text(*area));
      }
      check_bbox(a, path, image);
      if (a.contains("segmentation")) check_segmentation(a["segmentation"], path + ".segmentation");
      check_keypoints(a, path, image, category);
    }
  }

  void check_bbox(const json& a, const std::string& path, const ImageInfo* image) {
    const std::string p = path + ".bbox";
    if (!a.contains("bbox")) {
      add(Severity::kStructure, p, "missing");
      return;
    }
    const json& b = a["bbox"];
    if (!b.is_array() || b.size() != 4) {
      add(Severity::kStructure, p, "expected [x, y, width, height]");
      return;
    }
    double v[4];
    for (int k = 0; k < 4; ++k) {
      const auto d = number(b[k], at(p, k));
      if (!d) return;
      v[k] = *d;
    }
    if (v[2] <= 0 || v[3] <= 0) {
      add(Severity::kMeaning, p,
          "width and height must be positive, got " + number_text(v[2]) + " x " +
              number_text(v[3]));
    }
    if (image &&
        (v[0] < 0 || v[1] < 0 || v[0] + v[2] > image->width || v[1] + v[3] > image->height)) {
      add(Severity::kMeaning, p,
          "box [" + number_text(v[0]) + ", " + number_text(v[1]) + ", " + number_text(v[2]) + ", " +
              number_text(v[3]) + "] extends outside the " + number_text(image->width) + "x" +
              number_text(image->height) + " image");
    }
  }

  void check_segmentation(const json& s, const std::string& path) {
    if (s.is_object()) return;  // RLE: {counts, size}
    if (!s.is_array()) {
      add(Severity::kStructure, path, "expected a list of polygons or an RLE object");
      return;
    }
    for (std::size_t j = 0; j < s.size(); ++j) {
      const json& poly = s[j];
      if (!poly.is_array() || poly.size() < 6 || poly.size() % 2 != 0) {
        add(Severity::kStructure, at(path, j), "a polygon needs an even count >= 6 of numbers");
        continue;
      }
      for (std::size_t k = 0; k < poly.size(); ++k) {
        if (!poly[k].is_number()) {
          add(Severity::kStructure, at(at(path, j), k), "expected a number, got " + poly[k].dump());
          break;
        }
      }
    }
  }

  void check_keypoints(const json& a, const std::string& path, const ImageInfo* image,
                       const CategoryInfo* category) {
    const bool has_kp = a.contains("keypoints");
    const bool has_num = a.contains("num_keypoints");
    if (category && category->num_keypoints > 0) {
      if (!has_kp) add(Severity::kStructure, path + ".keypoints", "missing");
      if (!has_num) add(Severity::kStructure, path + ".num_keypoints", "missing");
    }
    if (!has_kp) return;
    const json& k = a["keypoints"];
    const std::string p = path + ".keypoints";
    if (!k.is_array()) {
      add(Severity::kStructure, p, "expected an array of x, y, v triples");
      return;
    }
    if (category && k.size() != static_cast<std::size_t>(3 * category->num_keypoints)) {
      add(Severity::kStructure, p,
          "expected " + std::to_string(3 * category->num_keypoints) + " numbers (" +
              std::to_string(category->num_keypoints) + " keypoints x 3), got " +
              std::to_string(k.size()));
      return;
    }
    if (k.size() % 3 != 0) {
      add(Severity::kStructure, p,
          "length " + std::to_string(k.size()) + " is not a multiple of 3");
      return;
    }
    int labelled = 0;
    bool all_numbers = true;
    for (std::size_t j = 0; j * 3 < k.size(); ++j) {
      std::string kp = at(p, j);
      if (category && j < category->names.size()) kp += " (" + category->names[j] + ")";
      const json &x = k[3 * j], &y = k[3 * j + 1], &v = k[3 * j + 2];
      if (!x.is_number() || !y.is_number() || !std::isfinite(x.get<double>()) ||
          !std::isfinite(y.get<double>())) {
        add(Severity::kStructure, kp,
            "x and y must be finite numbers, got " + x.dump() + ", " + y.dump());
        all_numbers = false;
        continue;
      }
      const auto vis = as_integer(v);
      if (!vis || *vis < 0 || *vis > 2) {
        add(Severity::kStructure, kp, "visibility must be 0, 1 or 2, got " + v.dump());
        all_numbers = false;
        continue;
      }
      const double xd = x.get<double>(), yd = y.get<double>();
      if (*vis == 0) {
        if (xd != 0 || yd != 0) {
          add(Severity::kMeaning, kp,
              "unlabelled (v=0) but at (" + number_text(xd) + ", " + number_text(yd) +
                  "), not (0, 0)");
        }
        continue;
      }
      ++labelled;
      if (image && (xd < 0 || yd < 0 || xd > image->width || yd > image->height)) {
        add(Severity::kMeaning, kp,
            "v=" + std::to_string(*vis) + " but (" + number_text(xd) + ", " + number_text(yd) +
                ") lies outside the " + number_text(image->width) + "x" +
                number_text(image->height) + " image");
      }
    }
    if (has_num && all_numbers) {
      const auto n = as_integer(a["num_keypoints"]);
      if (!n) {
        add(Severity::kStructure, path + ".num_keypoints",
            "expected an integer, got " + a["num_keypoints"].dump());
      } else if (*n != labelled) {
        add(Severity::kMeaning, path + ".num_keypoints",
            "is " + std::to_string(*n) + " but " + std::to_string(labelled) +
                " keypoints have v > 0");
      }
    }
  }

  const ValidateOptions& options_;
  std::vector<Problem> problems_;
  std::unordered_map<std::int64_t, ImageInfo> images_;
  std::unordered_map<std::int64_t, CategoryInfo> categories_;
};

}  // namespace

json load_json(const std::filesystem::path& path) { return coco::parse_json_file(path); }

std::optional<std::int64_t> as_integer(const json& v) {
  if (v.is_number_integer()) return v.get<std::int64_t>();
  if (v.is_number_float()) {
    const double d = v.get<double>();
    if (std::isfinite(d) && d == std::floor(d) && std::fabs(d) < 9e15) {
      return static_cast<std::int64_t>(d);
    }
  }
  return std::nullopt;
}

namespace {
std::string compact(const json& value) {
  return value.dump(-1, ' ', false, json::error_handler_t::replace);
}
}  // namespace

CanonicalCocoWriter::CanonicalCocoWriter(std::function<void(const std::string&)> sink)
    : sink_(std::move(sink)) {
  sink_("{\n");
}

void CanonicalCocoWriter::key(const std::string& name) {
  sink_((first_member_ ? "" : ",\n") + json(name).dump() + ": ");
  first_member_ = false;
}

void CanonicalCocoWriter::member(const std::string& name, const json& value) {
  if (value.is_array()) {
    begin_array(name);
    for (const json& e : value) element(e);
    end_array();
    return;
  }
  key(name);
  sink_(compact(value));
}

void CanonicalCocoWriter::begin_array(const std::string& name) {
  key(name);
  sink_("[");
  array_empty_ = true;
}

void CanonicalCocoWriter::element(const json& value) {
  sink_((array_empty_ ? "\n" : ",\n") + compact(value));
  array_empty_ = false;
}

void CanonicalCocoWriter::end_array() { sink_(array_empty_ ? "]" : "\n]"); }

void CanonicalCocoWriter::finish() { sink_("\n}\n"); }

std::string canonical_coco_text(json root) {
  if (!root.is_object()) return root.dump() + "\n";
  auto sort_by = [&](const char* array, const char* k1, const char* k2) {
    auto it = root.find(array);
    if (it == root.end() || !it->is_array()) return;
    std::stable_sort(it->begin(), it->end(), [&](const json& a, const json& b) {
      const auto ka = key_of(a, k1), kb = key_of(b, k1);
      if (ka != kb) return ka < kb;
      return k2 != nullptr && key_of(a, k2) < key_of(b, k2);
    });
  };
  sort_by("images", "id", nullptr);
  sort_by("annotations", "image_id", "id");
  sort_by("categories", "id", nullptr);
  std::string out;
  CanonicalCocoWriter writer([&out](const std::string& text) { out += text; });
  for (const auto& [key, value] : root.items())  // nlohmann's object keeps keys sorted
    writer.member(key, value);
  writer.finish();
  return out;
}

void write_coco(const std::filesystem::path& path, json root) {
  write_file_atomic(path, canonical_coco_text(std::move(root)));
}

std::vector<Problem> validate_coco(const json& root, const ValidateOptions& options) {
  return Validator(options).run(root);
}

void require_usable(const json& root, const std::string& source) {
  const std::vector<Problem> problems = validate_coco(root);
  std::size_t structural = 0, meaning = 0;
  const Problem* first = nullptr;
  for (const Problem& p : problems) {
    if (p.severity == Severity::kStructure) {
      if (!first) first = &p;
      ++structural;
    } else {
      ++meaning;
    }
  }
  if (first) {
    std::string more;
    if (structural > 1) {
      more = " (and " + std::to_string(structural - 1) + " more; see `wheelpose coco validate " +
             source + "`)";
    }
    throw Error(source + ": " + first->path + ": " + first->message + more);
  }
  if (meaning > 0) {
    spdlog::warn("{}: {} problem(s) of meaning (e.g. {}: {}); see `wheelpose coco validate`",
                 source, meaning, problems.front().path, problems.front().message);
  }
}

std::vector<std::int64_t> image_ids(const json& root) {
  std::vector<std::int64_t> ids;
  for (const json& im : root["images"]) ids.push_back(*as_integer(im["id"]));
  return ids;
}

}  // namespace wheelpose::dataset
