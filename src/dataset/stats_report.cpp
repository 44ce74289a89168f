#include "dataset/stats_report.h"

// Figures: dataset/plot.h (PLplot).
#include <plplot/plplot.h>

#include <algorithm>

#include "core/atomic_file.h"
#include "core/html.h"
#include "dataset/plot.h"

namespace wheelpose::dataset {
namespace {

namespace fs = std::filesystem;
using plot::bar;
using plot::panel;
using plot::render;

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

using Datasets = std::vector<DatasetStats>;

// The dataset's colour, and the reference's.
int colour(int d) { return d == 0 ? 2 : 3; }

// People per image, relative box size and box centres.
void box_figures(const Datasets& data, const fs::path& out_dir, std::vector<std::string>& figures) {
  const int nd = static_cast<int>(data.size());
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
}

// P(v = 0, 1, 2) per keypoint, the datasets side by side.
void visibility_figure(const Datasets& data, const fs::path& out_dir,
                       std::vector<std::string>& figures) {
  const int nd = static_cast<int>(data.size());
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
}

// Where the mapped keypoints fall in their box, one row per dataset.
void keypoint_location_figure(const Datasets& data, const fs::path& out_dir,
                              std::vector<std::string>& figures) {
  const int nd = static_cast<int>(data.size());
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
}

// Camera elevation, azimuth, distance and directions around the people, for datasets with a
// camera.
void camera_figure(const Datasets& data, const fs::path& out_dir,
                   std::vector<std::string>& figures) {
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
}

std::string report_html(const Datasets& data, const std::vector<std::string>& figures) {
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
  return html;
}

}  // namespace

std::vector<std::string> write_stats_report(const std::vector<DatasetStats>& data,
                                            const fs::path& out_dir) {
  ensure_directory(out_dir);
  std::vector<std::string> figures;
  box_figures(data, out_dir, figures);
  visibility_figure(data, out_dir, figures);
  keypoint_location_figure(data, out_dir, figures);
  camera_figure(data, out_dir, figures);
  json report = {{"datasets", json::array()}, {"figures", figures}};
  for (const auto& d : data) report["datasets"].push_back(stats_to_json(d));
  write_file_atomic(out_dir / "stats.json", report.dump(1) + "\n");
  write_file_atomic(out_dir / "index.html", report_html(data, figures));
  return figures;
}

}  // namespace wheelpose::dataset
