#include "dataset/coco_tools.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <numeric>
#include <set>
#include <tuple>
#include <unordered_map>
#include <unordered_set>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/random.h"

namespace wheelpose::dataset {
namespace {

std::int64_t int_field(const json& object, const char* key) { return *as_integer(object.at(key)); }

// Images sorted by id (positions into root["images"]).
std::vector<std::size_t> images_by_id(const json& root) {
  const json& images = root["images"];
  std::vector<std::size_t> order(images.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return int_field(images[a], "id") < int_field(images[b], "id");
  });
  return order;
}

// What must agree between merged files: per category id, its name and keypoint names.
json category_signature(const json& root) {
  json sig = json::object();
  for (const json& c : root["categories"]) {
    sig[std::to_string(int_field(c, "id"))] = {{"name", c["name"]},
                                               {"keypoints", c.value("keypoints", json::array())}};
  }
  return sig;
}

// root with only the images in `keep` (by id) and their annotations; ids unchanged.
json subset(const json& root, const std::unordered_set<std::int64_t>& keep) {
  json out = root;
  json images = json::array(), annotations = json::array();
  for (const json& im : root["images"]) {
    if (keep.count(int_field(im, "id"))) images.push_back(im);
  }
  for (const json& a : root["annotations"]) {
    if (keep.count(int_field(a, "image_id"))) annotations.push_back(a);
  }
  out["images"] = std::move(images);
  out["annotations"] = std::move(annotations);
  return out;
}

std::string motion_key(const json& object) {
  const auto it = object.find("motion_id");
  return it == object.end() || it->is_null() ? std::string() : it->dump();
}

struct UnionFind {
  std::vector<std::size_t> parent;
  explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  std::size_t find(std::size_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void unite(std::size_t a, std::size_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
};

std::string fixed6(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6f", v);
  return buf;
}

}  // namespace

json merge_coco(const std::vector<NamedCoco>& inputs, bool replace_by_filename) {
  if (inputs.empty()) throw Error("coco merge: no input files");
  for (const NamedCoco& in : inputs) require_usable(in.root, in.source);
  const json signature = category_signature(inputs[0].root);
  for (std::size_t k = 1; k < inputs.size(); ++k) {
    if (category_signature(inputs[k].root) != signature) {
      throw Error(inputs[k].source + ": categories differ from " + inputs[0].source +
                  " (ids, names or keypoint names); merge needs the same categories");
    }
  }

  json out = inputs[0].root;
  json images = json::array();
  // New image id of (input, old id); file name -> new id and origin.
  std::vector<std::unordered_map<std::int64_t, std::int64_t>> new_image_id(inputs.size());
  std::unordered_map<std::string, std::pair<std::int64_t, std::size_t>> by_name;
  std::unordered_map<std::int64_t, std::size_t> replaced_by;  // new image id -> input index
  std::int64_t next_image = 1;
  for (std::size_t k = 0; k < inputs.size(); ++k) {
    const json& root = inputs[k].root;
    const json& in_images = root["images"];
    for (std::size_t pos : images_by_id(root)) {
      const json& im = in_images[pos];
      const std::string name = im["file_name"].get<std::string>();
      const std::int64_t old_id = int_field(im, "id");
      if (replace_by_filename && k > 0) {
        const auto it = by_name.find(name);
        if (it == by_name.end()) {
          throw Error(inputs[k].source + ": images[" + std::to_string(pos) + "].file_name: '" +
                      name + "' is not an image of the base " + inputs[0].source);
        }
        new_image_id[k][old_id] = it->second.first;
        replaced_by[it->second.first] = k;
        continue;
      }
      const auto [it, inserted] = by_name.emplace(name, std::make_pair(next_image, k));
      if (!inserted && it->second.second != k) {
        throw Error(inputs[k].source + ": images[" + std::to_string(pos) + "].file_name: '" + name +
                    "' is also an image of " + inputs[it->second.second].source +
                    " (use --replace-by-filename to relabel)");
      }
      json copy = im;
      copy["id"] = next_image;
      new_image_id[k][old_id] = next_image++;
      images.push_back(std::move(copy));
    }
  }

  // (new image id, input, old annotation id, input, position)
  std::vector<std::tuple<std::int64_t, std::size_t, std::int64_t, std::size_t>> order;
  for (std::size_t k = 0; k < inputs.size(); ++k) {
    const json& anns = inputs[k].root["annotations"];
    for (std::size_t pos = 0; pos < anns.size(); ++pos) {
      const std::int64_t image = new_image_id[k].at(int_field(anns[pos], "image_id"));
      if (replace_by_filename) {
        const auto it = replaced_by.find(image);
        const std::size_t owner = it == replaced_by.end() ? 0 : it->second;
        if (owner != k) continue;
      }
      order.emplace_back(image, k, int_field(anns[pos], "id"), pos);
    }
  }
  std::sort(order.begin(), order.end());
  json annotations = json::array();
  std::int64_t next_annotation = 1;
  for (const auto& [image, k, old_id, pos] : order) {
    json a = inputs[k].root["annotations"][pos];
    a["id"] = next_annotation++;
    a["image_id"] = image;
    annotations.push_back(std::move(a));
  }
  out["images"] = std::move(images);
  out["annotations"] = std::move(annotations);
  return out;
}

json sample_coco(const json& root, const std::string& source, std::int64_t n, bool even,
                 std::uint64_t seed) {
  require_usable(root, source);
  const std::vector<std::size_t> order = images_by_id(root);
  const auto total = static_cast<std::int64_t>(order.size());
  if (n < 1 || n > total) {
    throw Error(source + ": cannot sample " + std::to_string(n) + " of " + std::to_string(total) +
                " images (--n must be in 1.." + std::to_string(total) + ")");
  }
  std::vector<std::int64_t> picked;  // positions into `order`
  if (even) {
    for (std::int64_t i = 0; i < n; ++i) {
      // round(i * (total-1) / (n-1)), halves up, in integers so it is exact.
      picked.push_back(n == 1 ? 0 : (2 * i * (total - 1) + (n - 1)) / (2 * (n - 1)));
    }
  } else {
    std::vector<std::int64_t> all(order.size());
    std::iota(all.begin(), all.end(), 0);
    RandomStream stream(seed, {"coco-sample"});
    for (std::int64_t i = 0; i < n; ++i) {
      std::swap(all[i], all[stream.uniform_int(i, total - 1)]);
    }
    picked.assign(all.begin(), all.begin() + n);
  }
  std::unordered_set<std::int64_t> keep;
  for (std::int64_t p : picked) keep.insert(int_field(root["images"][order[p]], "id"));
  return subset(root, keep);
}

std::vector<SplitPart> split_coco(const json& root, const std::vector<double>& ratios,
                                  const std::vector<std::string>& names, GroupBy group_by,
                                  std::uint64_t seed) {
  if (ratios.empty() || ratios.size() != names.size()) throw Error("split: one name per ratio");
  double sum = 0;
  for (double r : ratios) {
    if (!(r >= 0) || !std::isfinite(r)) throw Error("split: ratios must be >= 0");
    sum += r;
  }
  if (sum <= 0) throw Error("split: ratios must not all be 0");

  const json& images = root["images"];
  const std::vector<std::size_t> order = images_by_id(root);
  std::unordered_map<std::int64_t, std::size_t> rank;  // image id -> rank in id order
  for (std::size_t r = 0; r < order.size(); ++r) rank[int_field(images[order[r]], "id")] = r;

  UnionFind groups(order.size());
  if (group_by == GroupBy::kMotion) {
    std::unordered_map<std::string, std::size_t> first_with_motion;
    auto link = [&](const std::string& motion, std::size_t r) {
      if (motion.empty()) return;
      const auto [it, inserted] = first_with_motion.emplace(motion, r);
      if (!inserted) groups.unite(it->second, r);
    };
    for (std::size_t r = 0; r < order.size(); ++r) link(motion_key(images[order[r]]), r);
    for (const json& a : root["annotations"]) {
      link(motion_key(a), rank.at(int_field(a, "image_id")));
    }
  }
  // Groups in order of their first image, then shuffled.
  std::map<std::size_t, std::vector<std::size_t>> members;
  for (std::size_t r = 0; r < order.size(); ++r) members[groups.find(r)].push_back(r);
  std::vector<const std::vector<std::size_t>*> shuffled;
  for (const auto& [root_rank, m] : members) shuffled.push_back(&m);
  RandomStream stream(seed, {"coco-split"});
  for (std::size_t i = shuffled.size(); i > 1; --i) {
    std::swap(shuffled[i - 1], shuffled[stream.uniform_int(0, static_cast<std::int64_t>(i) - 1)]);
  }

  std::vector<double> count(ratios.size(), 0.0);
  std::vector<std::unordered_set<std::int64_t>> keep(ratios.size());
  const double total = static_cast<double>(order.size());
  for (const auto* group : shuffled) {
    std::size_t best = ratios.size();
    double best_deficit = 0;
    for (std::size_t k = 0; k < ratios.size(); ++k) {
      if (ratios[k] <= 0) continue;
      const double deficit = ratios[k] / sum * total - count[k];
      if (best == ratios.size() || deficit > best_deficit) {
        best = k;
        best_deficit = deficit;
      }
    }
    count[best] += static_cast<double>(group->size());
    for (std::size_t r : *group) keep[best].insert(int_field(images[order[r]], "id"));
  }
  std::vector<SplitPart> parts;
  for (std::size_t k = 0; k < ratios.size(); ++k)
    parts.push_back({names[k], subset(root, keep[k])});
  return parts;
}

std::size_t export_yolo_pose(const json& root, const std::string& source,
                             const KeypointTemplate& keypoint_template,
                             const std::filesystem::path& out_dir) {
  require_usable(root, source);
  // Classes are the categories in id order; all keypoint categories must share one length.
  std::map<std::int64_t, std::size_t> class_of;
  std::vector<std::string> class_names;
  std::vector<std::string> kp_names;
  bool have_kp = false;
  std::vector<json> categories(root["categories"].begin(), root["categories"].end());
  std::sort(categories.begin(), categories.end(),
            [](const json& a, const json& b) { return int_field(a, "id") < int_field(b, "id"); });
  for (const json& c : categories) {
    class_of[int_field(c, "id")] = class_names.size();
    class_names.push_back(c["name"].get<std::string>());
    if (!c.contains("keypoints") || c["keypoints"].empty()) continue;
    const auto names = c["keypoints"].get<std::vector<std::string>>();
    if (have_kp && names.size() != kp_names.size()) {
      throw Error(source + ": categories have different keypoint counts; YOLO-pose needs one");
    }
    if (!have_kp) kp_names = names;
    have_kp = true;
  }
  if (!have_kp) throw Error(source + ": no category has keypoints; nothing to export as pose");
  const std::size_t nk = kp_names.size();

  std::vector<std::size_t> flip(nk);
  std::iota(flip.begin(), flip.end(), 0);
  std::size_t unknown = 0;
  for (std::size_t i = 0; i < nk; ++i) {
    const int t = keypoint_template.index_of(kp_names[i]);
    if (t < 0) {
      ++unknown;
      continue;
    }
    for (const auto& [a, b] : keypoint_template.flip_pairs) {
      const int partner = a == t ? b : b == t ? a : -1;
      if (partner < 0) continue;
      const auto it =
          std::find(kp_names.begin(), kp_names.end(), keypoint_template.keypoints[partner].name);
      if (it != kp_names.end()) flip[i] = static_cast<std::size_t>(it - kp_names.begin());
    }
  }
  if (unknown > 0) {
    spdlog::warn("{}: {} keypoint name(s) not in template '{}'; they flip onto themselves", source,
                 unknown, keypoint_template.name);
  }

  std::unordered_map<std::int64_t, std::vector<const json*>> by_image;
  for (const json& a : root["annotations"]) by_image[int_field(a, "image_id")].push_back(&a);
  ensure_directory(out_dir / "labels");
  std::unordered_map<std::string, std::string> stems;
  std::size_t lines = 0;
  for (std::size_t pos : images_by_id(root)) {
    const json& im = root["images"][pos];
    const std::string file = im["file_name"].get<std::string>();
    const std::string stem = std::filesystem::path(file).stem().string();
    const auto [it, inserted] = stems.emplace(stem, file);
    if (!inserted) {
      throw Error(source + ": images[" + std::to_string(pos) + "].file_name '" + file +
                  "' has the same label name as '" + it->second + "' (" + stem + ".txt)");
    }
    const double w = static_cast<double>(int_field(im, "width"));
    const double h = static_cast<double>(int_field(im, "height"));
    auto clamp01 = [](double v) { return std::clamp(v, 0.0, 1.0); };
    std::string text;
    auto& anns = by_image[int_field(im, "id")];
    std::sort(anns.begin(), anns.end(), [](const json* a, const json* b) {
      return int_field(*a, "id") < int_field(*b, "id");
    });
    for (const json* a : anns) {
      if (a->value("iscrowd", 0) != 0) continue;
      const json& b = (*a)["bbox"];
      const double bx = b[0].get<double>(), by = b[1].get<double>();
      const double bw = b[2].get<double>(), bh = b[3].get<double>();
      if (bw <= 0 || bh <= 0) continue;
      const double x0 = clamp01(bx / w), y0 = clamp01(by / h);
      const double x1 = clamp01((bx + bw) / w), y1 = clamp01((by + bh) / h);
      text += std::to_string(class_of.at(int_field(*a, "category_id"))) + " " +
              fixed6((x0 + x1) / 2) + " " + fixed6((y0 + y1) / 2) + " " + fixed6(x1 - x0) + " " +
              fixed6(y1 - y0);
      const json& kp = a->value("keypoints", json::array());
      for (std::size_t k = 0; k < nk; ++k) {
        const int v = kp.size() == 3 * nk ? static_cast<int>(*as_integer(kp[3 * k + 2])) : 0;
        if (v == 0) {
          text += " 0.000000 0.000000 0";
        } else {
          text += " " + fixed6(clamp01(kp[3 * k].get<double>() / w)) + " " +
                  fixed6(clamp01(kp[3 * k + 1].get<double>() / h)) + " " + std::to_string(v);
        }
      }
      text += "\n";
      ++lines;
    }
    write_file_atomic(out_dir / "labels" / (stem + ".txt"), text);
  }

  std::string yaml = "# Ultralytics YOLO-pose dataset written by `wheelpose coco export` from " +
                     json(source).dump() +
                     ".\n# Put (or link) the images in images/ beside labels/; label files are "
                     "named after the image file stems.\n";
  yaml += "path: " + json(std::filesystem::absolute(out_dir).lexically_normal().string()).dump() +
          "\ntrain: images\nval: images\n";
  yaml += "kpt_shape: [" + std::to_string(nk) + ", 3]\nflip_idx: [";
  for (std::size_t i = 0; i < nk; ++i) yaml += (i ? ", " : "") + std::to_string(flip[i]);
  yaml += "]\nnames:\n";
  for (std::size_t c = 0; c < class_names.size(); ++c) {
    yaml += "  " + std::to_string(c) + ": " + json(class_names[c]).dump() + "\n";
  }
  yaml += "# keypoints:";
  for (std::size_t i = 0; i < nk; ++i) yaml += " " + std::to_string(i) + "=" + kp_names[i];
  yaml += "\n";
  write_file_atomic(out_dir / "data.yaml", yaml);
  return lines;
}

}  // namespace wheelpose::dataset
