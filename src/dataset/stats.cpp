#include "dataset/stats.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <unordered_map>

#include "core/error.h"

namespace wheelpose::dataset {
namespace {

constexpr double kPi = std::numbers::pi;
const char* const kMapKeypoints[] = {"nose",       "left_wrist", "right_wrist", "left_knee",
                                     "right_knee", "left_ankle", "right_ankle"};

std::int64_t int_of(const json& v) { return *as_integer(v); }

// ---- statistics -------------------------------------------------------------------------

std::vector<double> numbers(const json& a) {
  std::vector<double> out;
  out.reserve(a.size());
  for (const json& v : a) out.push_back(v.get<double>());
  return out;
}

}  // namespace

std::int64_t Histogram::total() const {
  std::int64_t t = 0;
  for (auto c : counts) t += c;
  return t;
}

void Histogram::add(double value) {
  const auto n = static_cast<std::int64_t>(counts.size());
  auto bin = static_cast<std::int64_t>(std::floor((value - lo) / (hi - lo) * n));
  ++counts[std::clamp<std::int64_t>(bin, 0, n - 1)];
}

void Grid::add(double x, double y) {
  const int cx = std::clamp(static_cast<int>(std::floor(x * nx)), 0, nx - 1);
  const int cy = std::clamp(static_cast<int>(std::floor(y * ny)), 0, ny - 1);
  ++counts[static_cast<std::size_t>(cy) * nx + cx];
}

std::int64_t Grid::total() const {
  std::int64_t t = 0;
  for (auto c : counts) t += c;
  return t;
}

std::pair<int, int> Grid::peak() const {
  const auto it = std::max_element(counts.begin(), counts.end());
  const int index = static_cast<int>(it - counts.begin());
  return {index % nx, index / nx};
}

namespace {

// Where the keypoints the statistics need sit in the dataset's keypoint list.
struct KeypointLayout {
  std::unordered_map<std::int64_t, int> count_by_category;  // category id -> K
  std::vector<int> map_index;                               // per DatasetStats::keypoint_maps entry
  int nose = -1, left_hip = -1, right_hip = -1;
};

// Sets up s's empty histograms and grids and its keypoint names (the first category's that has
// any), and returns where the mapped and camera keypoints are.
KeypointLayout start_stats(const json& root, DatasetStats& s) {
  s.box_size = Histogram{0, 1, std::vector<std::int64_t>(20)};
  s.box_centre = Grid{32, 32, std::vector<std::int64_t>(32 * 32)};
  s.elevation = Histogram{-kPi / 2, kPi / 2, std::vector<std::int64_t>(36)};
  s.azimuth = Histogram{-kPi, kPi, std::vector<std::int64_t>(36)};
  KeypointLayout layout;
  for (const json& c : root["categories"]) {
    const json& k = c.value("keypoints", json::array());
    layout.count_by_category[int_of(c["id"])] = static_cast<int>(k.size());
    if (s.keypoint_names.empty() && !k.empty())
      s.keypoint_names = k.get<std::vector<std::string>>();
  }
  s.visibility.assign(s.keypoint_names.size(), {0, 0, 0});
  auto index_of = [&](const char* name) {
    const auto it = std::find(s.keypoint_names.begin(), s.keypoint_names.end(), name);
    return it == s.keypoint_names.end() ? -1 : static_cast<int>(it - s.keypoint_names.begin());
  };
  for (const char* name : kMapKeypoints) {
    const int index = index_of(name);
    if (index < 0) continue;
    layout.map_index.push_back(index);
    s.keypoint_maps.push_back({name, Grid{24, 24, std::vector<std::int64_t>(24 * 24)}});
  }
  layout.nose = index_of("nose");
  layout.left_hip = index_of("left_hip");
  layout.right_hip = index_of("right_hip");
  return layout;
}

struct ImageInfo {
  double w, h;
  bool has_camera;
  double cx, cy, cz;
  std::int64_t people;
  std::array<double, 9> rotation{};  // camera → world, row-major
};

// Images by id, with their camera when camera.extrinsics holds 16 numbers.
std::unordered_map<std::int64_t, ImageInfo> read_images(const json& root,
                                                        std::int64_t& images_with_camera) {
  std::unordered_map<std::int64_t, ImageInfo> images;
  for (const json& im : root["images"]) {
    ImageInfo info{static_cast<double>(int_of(im["width"])),
                   static_cast<double>(int_of(im["height"])),
                   false,
                   0,
                   0,
                   0,
                   0};
    const auto c = im.find("camera");
    if (c != im.end() && c->is_object() && c->contains("extrinsics")) {
      const json& e = (*c)["extrinsics"];
      if (e.is_array() && e.size() == 16 &&
          std::all_of(e.begin(), e.end(), [](const json& v) { return v.is_number(); })) {
        info.has_camera = true;
        info.cx = e[3].get<double>();
        info.cy = e[7].get<double>();
        info.cz = e[11].get<double>();
        for (int r = 0; r < 3; ++r)
          for (int c2 = 0; c2 < 3; ++c2) info.rotation[3 * r + c2] = e[4 * r + c2].get<double>();
        ++images_with_camera;
      }
    }
    images.emplace(int_of(im["id"]), info);
  }
  return images;
}

// One person's box, and its keypoints' visibility and place in the box; false when the
// keypoints do not follow the dataset's layout (the camera analysis needs them).
bool add_instance(const json& a, const ImageInfo& image, const KeypointLayout& layout,
                  DatasetStats& s) {
  const int nk = static_cast<int>(s.keypoint_names.size());
  const auto box = numbers(a["bbox"]);
  s.box_size.add(std::sqrt(std::max(0.0, box[2] * box[3]) / (image.w * image.h)));
  s.box_centre.add((box[0] + box[2] / 2) / image.w, (box[1] + box[3] / 2) / image.h);
  const auto kp_it = a.find("keypoints");
  const auto category = layout.count_by_category.find(int_of(a["category_id"]));
  if (kp_it == a.end() || static_cast<int>(kp_it->size()) != 3 * nk || nk == 0 ||
      category == layout.count_by_category.end() || category->second != nk) {
    return false;
  }
  const std::vector<double> kp = numbers(*kp_it);
  int labelled = 0;
  for (int k = 0; k < nk; ++k) labelled += kp[3 * k + 2] > 0;
  if (labelled > 0) {
    ++s.labelled_instances;
    for (int k = 0; k < nk; ++k) ++s.visibility[k][static_cast<int>(kp[3 * k + 2])];
  }
  if (box[2] > 0 && box[3] > 0) {
    for (std::size_t m = 0; m < layout.map_index.size(); ++m) {
      const int k = layout.map_index[m];
      if (kp[3 * k + 2] <= 0) continue;
      s.keypoint_maps[m].grid.add((kp[3 * k] - box[0]) / box[2], (kp[3 * k + 1] - box[1]) / box[3]);
    }
  }
  return true;
}

// The camera seen from the person (stats.h): adds elevation and azimuth and returns the
// distance, or nothing without keypoints_3d of the nose and hips.
std::optional<double> add_camera_view(const json& a, const ImageInfo& image,
                                      const KeypointLayout& layout, std::int64_t seen,
                                      DatasetStats& s) {
  const int nk = static_cast<int>(s.keypoint_names.size());
  const auto k3 = a.find("keypoints_3d");
  if (k3 == a.end() || static_cast<int>(k3->size()) != 3 * nk || layout.nose < 0 ||
      layout.left_hip < 0 || layout.right_hip < 0) {
    return std::nullopt;
  }
  // keypoints_3d are in camera space; the extrinsics take them to the world.
  const std::vector<double> p = numbers(*k3);
  auto P = [&](int k, int axis) {
    const double t = axis == 0 ? image.cx : axis == 1 ? image.cy : image.cz;
    const double* row = &image.rotation[3 * axis];
    return t + row[0] * p[3 * k] + row[1] * p[3 * k + 1] + row[2] * p[3 * k + 2];
  };
  const double dx = image.cx - P(layout.nose, 0), dy = image.cy - P(layout.nose, 1),
               dz = image.cz - P(layout.nose, 2);
  double lx = P(layout.left_hip, 0) - P(layout.right_hip, 0);
  double lz = P(layout.left_hip, 2) - P(layout.right_hip, 2);
  const double ll = std::hypot(lx, lz), dist = std::sqrt(dx * dx + dy * dy + dz * dz);
  if (ll <= 0 || dist <= 0) return std::nullopt;
  lx /= ll;
  lz /= ll;
  // forward = left x up with up = (0, 1, 0): (-lz, 0, lx); right = -left.
  const double fx = -lz, fz = lx;
  const double along_right = -(dx * lx + dz * lz), along_forward = dx * fx + dz * fz;
  s.elevation.add(std::asin(std::clamp(dy / dist, -1.0, 1.0)));
  s.azimuth.add(std::atan2(along_right, along_forward));
  if (seen % 100 == 0) {
    s.directions.push_back({along_right / dist, dy / dist, along_forward / dist});
  }
  return dist;
}

}  // namespace

DatasetStats compute_stats(const json& root, const std::string& source, const std::string& label) {
  DatasetStats s;
  s.label = label;
  s.source = source;
  const KeypointLayout layout = start_stats(root, s);
  std::int64_t images_with_camera = 0;
  std::unordered_map<std::int64_t, ImageInfo> images = read_images(root, images_with_camera);
  s.images = static_cast<std::int64_t>(images.size());

  std::vector<double> distances;
  std::int64_t people_with_3d = 0, camera_people = 0;
  for (const json& a : root["annotations"]) {
    if (a.value("iscrowd", 0) != 0) continue;
    ImageInfo& image = images.at(int_of(a["image_id"]));
    ++s.instances;
    ++image.people;
    if (!add_instance(a, image, layout, s) || !image.has_camera) continue;
    ++camera_people;
    if (auto distance = add_camera_view(a, image, layout, people_with_3d, s)) {
      distances.push_back(*distance);
      ++people_with_3d;
    }
  }
  for (const auto& [id, image] : images) {
    if (image.people == 0) continue;
    ++s.images_with_people;
    if (static_cast<std::int64_t>(s.boxes_per_image.size()) < image.people) {
      s.boxes_per_image.resize(image.people, 0);
    }
    ++s.boxes_per_image[image.people - 1];
  }
  s.has_camera = people_with_3d > 0;
  if (images_with_camera == 0) {
    s.camera_note = "no image has camera.extrinsics; camera analysis skipped";
  } else if (people_with_3d < camera_people) {
    s.camera_note = std::to_string(camera_people - people_with_3d) + " of " +
                    std::to_string(camera_people) +
                    " people in images with a camera lack keypoints_3d (nose and hips); skipped";
  }
  double max_distance = 1;
  for (double d : distances) max_distance = std::max(max_distance, d);
  s.distance = Histogram{0, std::ceil(max_distance), std::vector<std::int64_t>(30)};
  for (double d : distances) s.distance.add(d);
  return s;
}

json stats_to_json(const DatasetStats& s) {
  auto hist = [](const Histogram& h) {
    return json{{"lo", h.lo}, {"hi", h.hi}, {"counts", h.counts}, {"total", h.total()}};
  };
  auto grid = [](const Grid& g) {
    const auto [px, py] = g.peak();
    return json{
        {"columns", g.nx},
        {"rows", g.ny},
        {"counts", g.counts},
        {"total", g.total()},
        {"peak",
         {{"column", px}, {"row", py}, {"x", (px + 0.5) / g.nx}, {"y", (py + 0.5) / g.ny}}}};
  };
  json j;
  j["label"] = s.label;
  j["source"] = s.source;
  j["counts"] = {{"images", s.images},
                 {"instances", s.instances},
                 {"labelled_instances", s.labelled_instances},
                 {"images_with_people", s.images_with_people}};
  j["boxes_per_image"] = {{"note", "counts[k-1] = images with k people; images without excluded"},
                          {"counts", s.boxes_per_image}};
  j["relative_box_size"] = hist(s.box_size);
  j["box_centre"] = grid(s.box_centre);
  json vis = {{"keypoints", s.keypoint_names},
              {"note", "over instances with >= 1 labelled keypoint"},
              {"not_visible", json::array()},
              {"occluded", json::array()},
              {"visible", json::array()}};
  const double n = static_cast<double>(std::max<std::int64_t>(1, s.labelled_instances));
  for (const auto& c : s.visibility) {
    vis["not_visible"].push_back(c[0] / n);
    vis["occluded"].push_back(c[1] / n);
    vis["visible"].push_back(c[2] / n);
  }
  j["keypoint_visibility"] = vis;
  json maps = json::object();
  for (const auto& m : s.keypoint_maps) maps[m.name] = grid(m.grid);
  j["keypoint_location"] = maps;
  json camera = {{"available", s.has_camera}};
  if (!s.camera_note.empty()) camera["note"] = s.camera_note;
  if (s.has_camera) {
    camera["elevation_rad"] = hist(s.elevation);
    camera["azimuth_rad"] = hist(s.azimuth);
    camera["distance_m"] = hist(s.distance);
    camera["directions_every_100th"] = s.directions;
  }
  j["camera"] = camera;
  return j;
}

}  // namespace wheelpose::dataset
