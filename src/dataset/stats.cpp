#include "dataset/stats.h"

// Figures: dataset/plot.h (PLplot).
#include <plplot/plplot.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <unordered_map>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/html.h"
#include "dataset/plot.h"

namespace wheelpose::dataset {
namespace {

namespace fs = std::filesystem;
using plot::bar;
using plot::panel;
using plot::render;
constexpr double kPi = std::numbers::pi;
const char* const kMapKeypoints[] = {"nose",       "left_wrist", "right_wrist", "left_knee",
                                     "right_knee", "left_ankle", "right_ankle"};

std::int64_t int_of(const json& v) { return *as_integer(v); }

// Histogram as a probability density (so datasets of different sizes compare).
void density_panel(const Histogram& h, int colour, const std::string& x_label,
                   const std::string& title) {
  const double total = static_cast<double>(std::max<std::int64_t>(1, h.total()));
  const double width = (h.hi - h.lo) / static_cast<double>(h.counts.size());
  double top = 0;
  for (auto c : h.counts) top = std::max(top, c / total / width);
  panel(h.lo, h.hi, 0, top > 0 ? top * 1.1 : 1, x_label, "density", title);
  for (std::size_t i = 0; i < h.counts.size(); ++i) {
    bar(h.lo + i * width, h.lo + (i + 1) * width, h.counts[i] / total / width, colour);
  }
}

void heatmap_panel(const Grid& g, const std::string& x_label, const std::string& y_label,
                   const std::string& title, bool mark_peak) {
  pladv(0);
  plvsta();
  plwind(0, 1, 1, 0);  // image convention: y grows downwards
  std::vector<std::vector<PLFLT>> columns(g.nx, std::vector<PLFLT>(g.ny));
  double top = 0;
  const double total = static_cast<double>(std::max<std::int64_t>(1, g.total()));
  for (int x = 0; x < g.nx; ++x) {
    for (int y = 0; y < g.ny; ++y) {
      // Row 0 is the top of the image, drawn at y = 0 of the flipped window.
      columns[x][y] = g.counts[static_cast<std::size_t>(y) * g.nx + x] / total;
      top = std::max(top, columns[x][y]);
    }
  }
  std::vector<const PLFLT*> rows;
  for (auto& c : columns) rows.push_back(c.data());
  plimage(rows.data(), g.nx, g.ny, 0, 1, 0, 1, 0, top > 0 ? top : 1, 0, 1, 0, 1);
  plcol0(1);
  plbox("bcnst", 0, 0, "bcnstv", 0, 0);
  pllab(x_label.c_str(), y_label.c_str(), title.c_str());
  if (mark_peak && g.total() > 0) {
    const auto [px, py] = g.peak();
    PLFLT x = (px + 0.5) / g.nx, y = (py + 0.5) / g.ny;
    plcol0(4);
    plschr(0, 1.6);
    plpoin(1, &x, &y, 5);
    plschr(0, 0.8);
    plptex(x + 0.03, y, 1, 0, 0, "peak");
  }
}

void note_panel(const std::string& title, const std::string& text) {
  pladv(0);
  plvpor(0.05, 0.95, 0.05, 0.95);
  plwind(0, 1, 0, 1);
  plcol0(1);
  plmtex("t", 1, 0.5, 0.5, title.c_str());
  plptex(0.5, 0.5, 1, 0, 0.5, text.c_str());
}

// ---- statistics -------------------------------------------------------------------------

std::vector<double> numbers(const json& a) {
  std::vector<double> out;
  out.reserve(a.size());
  for (const json& v : a) out.push_back(v.get<double>());
  return out;
}

struct CameraContext {
  int nose = -1, left_hip = -1, right_hip = -1;
};

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

DatasetStats compute_stats(const json& root, const std::string& source, const std::string& label) {
  DatasetStats s;
  s.label = label;
  s.source = source;
  s.box_size = Histogram{0, 1, std::vector<std::int64_t>(20)};
  s.box_centre = Grid{32, 32, std::vector<std::int64_t>(32 * 32)};
  s.elevation = Histogram{-kPi / 2, kPi / 2, std::vector<std::int64_t>(36)};
  s.azimuth = Histogram{-kPi, kPi, std::vector<std::int64_t>(36)};

  std::unordered_map<std::int64_t, int> keypoint_count;  // category id -> K
  for (const json& c : root["categories"]) {
    const json& k = c.value("keypoints", json::array());
    keypoint_count[int_of(c["id"])] = static_cast<int>(k.size());
    if (s.keypoint_names.empty() && !k.empty())
      s.keypoint_names = k.get<std::vector<std::string>>();
  }
  const int nk = static_cast<int>(s.keypoint_names.size());
  s.visibility.assign(nk, {0, 0, 0});
  std::vector<int> map_index;
  for (const char* name : kMapKeypoints) {
    const auto it = std::find(s.keypoint_names.begin(), s.keypoint_names.end(), name);
    if (it == s.keypoint_names.end()) continue;
    map_index.push_back(static_cast<int>(it - s.keypoint_names.begin()));
    s.keypoint_maps.push_back({name, Grid{24, 24, std::vector<std::int64_t>(24 * 24)}});
  }
  CameraContext cam;
  auto index_of = [&](const char* name) {
    const auto it = std::find(s.keypoint_names.begin(), s.keypoint_names.end(), name);
    return it == s.keypoint_names.end() ? -1 : static_cast<int>(it - s.keypoint_names.begin());
  };
  cam.nose = index_of("nose");
  cam.left_hip = index_of("left_hip");
  cam.right_hip = index_of("right_hip");

  struct ImageInfo {
    double w, h;
    bool has_camera;
    double cx, cy, cz;
    std::int64_t people;
    std::array<double, 9> rotation{};  // camera → world, row-major
  };
  std::unordered_map<std::int64_t, ImageInfo> images;
  std::int64_t images_with_camera = 0;
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
  s.images = static_cast<std::int64_t>(images.size());

  std::vector<double> distances;
  std::int64_t people_with_3d = 0, camera_people = 0;
  for (const json& a : root["annotations"]) {
    if (a.value("iscrowd", 0) != 0) continue;
    ImageInfo& image = images.at(int_of(a["image_id"]));
    ++s.instances;
    ++image.people;
    const auto box = numbers(a["bbox"]);
    s.box_size.add(std::sqrt(std::max(0.0, box[2] * box[3]) / (image.w * image.h)));
    s.box_centre.add((box[0] + box[2] / 2) / image.w, (box[1] + box[3] / 2) / image.h);
    const auto kp_it = a.find("keypoints");
    if (kp_it == a.end() || static_cast<int>(kp_it->size()) != 3 * nk || nk == 0 ||
        keypoint_count[int_of(a["category_id"])] != nk) {
      continue;
    }
    const std::vector<double> kp = numbers(*kp_it);
    int labelled = 0;
    for (int k = 0; k < nk; ++k) labelled += kp[3 * k + 2] > 0;
    if (labelled > 0) {
      ++s.labelled_instances;
      for (int k = 0; k < nk; ++k) ++s.visibility[k][static_cast<int>(kp[3 * k + 2])];
    }
    if (box[2] > 0 && box[3] > 0) {
      for (std::size_t m = 0; m < map_index.size(); ++m) {
        const int k = map_index[m];
        if (kp[3 * k + 2] <= 0) continue;
        s.keypoint_maps[m].grid.add((kp[3 * k] - box[0]) / box[2],
                                    (kp[3 * k + 1] - box[1]) / box[3]);
      }
    }
    // Camera around the person.
    if (!image.has_camera) continue;
    ++camera_people;
    const auto k3 = a.find("keypoints_3d");
    if (k3 == a.end() || static_cast<int>(k3->size()) != 3 * nk || cam.nose < 0 ||
        cam.left_hip < 0 || cam.right_hip < 0) {
      continue;
    }
    // keypoints_3d are in camera space; the extrinsics take them to the world.
    const std::vector<double> p = numbers(*k3);
    auto P = [&](int k, int axis) {
      const double t = axis == 0 ? image.cx : axis == 1 ? image.cy : image.cz;
      const double* row = &image.rotation[3 * axis];
      return t + row[0] * p[3 * k] + row[1] * p[3 * k + 1] + row[2] * p[3 * k + 2];
    };
    const double dx = image.cx - P(cam.nose, 0), dy = image.cy - P(cam.nose, 1),
                 dz = image.cz - P(cam.nose, 2);
    double lx = P(cam.left_hip, 0) - P(cam.right_hip, 0);
    double lz = P(cam.left_hip, 2) - P(cam.right_hip, 2);
    const double ll = std::hypot(lx, lz), dist = std::sqrt(dx * dx + dy * dy + dz * dz);
    if (ll <= 0 || dist <= 0) continue;
    lx /= ll;
    lz /= ll;
    // forward = left x up with up = (0, 1, 0): (-lz, 0, lx); right = -left.
    const double fx = -lz, fz = lx;
    const double along_right = -(dx * lx + dz * lz), along_forward = dx * fx + dz * fz;
    s.elevation.add(std::asin(std::clamp(dy / dist, -1.0, 1.0)));
    s.azimuth.add(std::atan2(along_right, along_forward));
    distances.push_back(dist);
    if (people_with_3d % 100 == 0) {
      s.directions.push_back({along_right / dist, dy / dist, along_forward / dist});
    }
    ++people_with_3d;
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

std::vector<std::string> write_stats_report(const std::vector<DatasetStats>& data,
                                            const fs::path& out_dir) {
  ensure_directory(out_dir);
  const int nd = static_cast<int>(data.size());
  std::vector<std::string> figures;
  auto colour = [](int d) { return d == 0 ? 2 : 3; };

  render(out_dir / "boxes_per_image", 560 * nd, 420, nd, 1, [&] {
    for (int d = 0; d < nd; ++d) {
      const auto& b = data[d].boxes_per_image;
      const double total =
          static_cast<double>(std::max<std::int64_t>(1, data[d].images_with_people));
      double top = 0;
      for (auto c : b) top = std::max(top, c / total);
      panel(0.5, std::max<double>(b.size(), 1) + 0.5, 0, top > 0 ? top * 1.1 : 1,
            "people per image", "fraction of images", data[d].label);
      for (std::size_t k = 0; k < b.size(); ++k) bar(k + 0.6, k + 1.4, b[k] / total, colour(d));
    }
  });
  figures.push_back("boxes_per_image");

  render(out_dir / "relative_box_size", 560 * nd, 420, nd, 1, [&] {
    for (int d = 0; d < nd; ++d) {
      density_panel(data[d].box_size, colour(d), "sqrt(box area / image area)", data[d].label);
    }
  });
  figures.push_back("relative_box_size");

  render(out_dir / "box_location", 480 * nd, 480, nd, 1, [&] {
    for (int d = 0; d < nd; ++d) {
      heatmap_panel(data[d].box_centre, "x / image width", "y / image height",
                    data[d].label + ": box centres", true);
    }
  });
  figures.push_back("box_location");

  const auto& names = data[0].keypoint_names;
  const int nk = static_cast<int>(names.size());
  if (nk > 0) {
    render(out_dir / "keypoint_visibility", 1000, 1200, 1, 3, [&] {
      const char* titles[] = {"not visible (v=0)", "occluded (v=1)", "visible (v=2)"};
      for (int level = 0; level < 3; ++level) {
        pladv(0);
        plvpor(0.08, 0.97, 0.25, 0.9);
        plwind(0, nk, 0, 1);
        plcol0(1);
        plbox("bc", 0, 0, "bcnstv", 0, 0);
        plmtex("t", 1.5, 0.5, 0.5, (std::string("P(") + titles[level] + ")").c_str());
        for (int k = 0; k < nk; ++k) {
          plmtex("bv", 0.5, (k + 0.5) / nk, 1.0, names[k].c_str());
          for (int d = 0; d < nd; ++d) {
            if (static_cast<int>(data[d].visibility.size()) != nk) continue;
            const double n =
                static_cast<double>(std::max<std::int64_t>(1, data[d].labelled_instances));
            const double x0 = k + 0.1 + 0.8 * d / nd;
            bar(x0, x0 + 0.8 / nd, data[d].visibility[k][level] / n, colour(d));
          }
        }
        for (int d = 0; d < nd; ++d) {
          plcol0(colour(d));
          plmtex("t", 0.3, 0.02 + 0.3 * d, 0.0, data[d].label.c_str());
        }
      }
    });
    figures.push_back("keypoint_visibility");
  }

  if (!data[0].keypoint_maps.empty()) {
    const int nm = static_cast<int>(data[0].keypoint_maps.size());
    render(out_dir / "keypoint_location", 300 * nm, 320 * nd, nm, nd, [&] {
      for (int d = 0; d < nd; ++d) {
        for (int m = 0; m < nm; ++m) {
          const KeypointMap* map = nullptr;
          for (const auto& km : data[d].keypoint_maps) {
            if (km.name == data[0].keypoint_maps[m].name) map = &km;
          }
          if (map == nullptr) {
            note_panel(data[d].label, "no " + data[0].keypoint_maps[m].name);
          } else {
            heatmap_panel(map->grid, "x in box", "y in box", data[d].label + ": " + map->name,
                          false);
          }
        }
      }
    });
    figures.push_back("keypoint_location");
  }

  std::vector<const DatasetStats*> with_camera;
  for (const auto& d : data) {
    if (d.has_camera) with_camera.push_back(&d);
  }
  if (!with_camera.empty()) {
    const int nc = static_cast<int>(with_camera.size());
    render(out_dir / "camera", 1600, 400 * nc, 4, nc, [&] {
      for (int i = 0; i < nc; ++i) {
        const DatasetStats& s = *with_camera[i];
        const int c = &s == &data[0] ? 2 : 3;
        density_panel(s.elevation, c, "elevation (rad)", s.label + ": camera elevation");
        density_panel(s.azimuth, c, "azimuth (rad)", s.label + ": camera azimuth");
        density_panel(s.distance, c, "distance (m)", s.label + ": camera distance");
        pladv(0);
        plvpor(0.0, 1.0, 0.0, 0.9);
        plwind(-1.0, 1.0, -0.9, 1.5);
        plw3d(1, 1, 1, -1, 1, -1, 1, -1, 1, 25, 30);
        plcol0(1);
        plbox3("bnstu", "right", 0, 0, "bnstu", "forward", 0, 0, "bcdmnstuv", "up", 0, 0);
        std::vector<PLFLT> x, y, z;
        for (const auto& d : s.directions) {
          x.push_back(d[0]);
          y.push_back(d[2]);
          z.push_back(d[1]);
        }
        plcol0(c);
        plpoin3(static_cast<PLINT>(x.size()), x.data(), y.data(), z.data(), 17);
        plcol0(1);
        plmtex("t", 0.5, 0.5, 0.5, (s.label + ": camera directions").c_str());
      }
    });
    figures.push_back("camera");
  }

  json report = {{"datasets", json::array()}, {"figures", figures}};
  for (const auto& d : data) report["datasets"].push_back(stats_to_json(d));
  write_file_atomic(out_dir / "stats.json", report.dump(1) + "\n");

  const auto esc = html_escape;
  std::string html =
      "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>Dataset "
      "statistics</title>\n<style>body{font-family:sans-serif;margin:2em}img{max-width:100%;"
      "border:1px solid #ccc}td,th{padding:4px 12px;text-align:right}</style></head><body>\n"
      "<h1>Dataset statistics</h1>\n<table><tr><th></th>";
  for (const auto& d : data) html += "<th>" + esc(d.label) + "</th>";
  html += "</tr>\n";
  auto row = [&](const char* name, auto get) {
    html += std::string("<tr><th>") + name + "</th>";
    for (const auto& d : data) html += "<td>" + std::to_string(get(d)) + "</td>";
    html += "</tr>\n";
  };
  row("images", [](const DatasetStats& d) { return d.images; });
  row("person instances", [](const DatasetStats& d) { return d.instances; });
  row("instances with a labelled keypoint",
      [](const DatasetStats& d) { return d.labelled_instances; });
  row("images with people", [](const DatasetStats& d) { return d.images_with_people; });
  html += "</table>\n<p>Sources: ";
  for (const auto& d : data) html += "<code>" + esc(d.source) + "</code> ";
  html += "&middot; every number is in <a href=\"stats.json\">stats.json</a></p>\n";
  for (const auto& f : figures) {
    html += "<h2>" + esc(f) + "</h2>\n<p><a href=\"" + f + ".svg\"><img src=\"" + f +
            ".png\" alt=\"" + f + "\"></a></p>\n";
  }
  for (const auto& d : data) {
    if (!d.camera_note.empty()) html += "<p>" + esc(d.label) + ": " + esc(d.camera_note) + "</p>\n";
  }
  html += "</body></html>\n";
  write_file_atomic(out_dir / "index.html", html);
  return figures;
}

}  // namespace wheelpose::dataset
