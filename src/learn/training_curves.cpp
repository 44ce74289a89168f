#include "learn/training_curves.h"

#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

#include "core/atomic_file.h"
#include "core/error.h"
#include "dataset/plot.h"

namespace wheelpose::learn {
namespace {

namespace fs = std::filesystem;
namespace plot = dataset::plot;

// A CSV of numbers with a header: one vector per column.
std::vector<std::vector<double>> read_columns(const fs::path& path, std::size_t columns) {
  std::vector<std::vector<double>> out(columns);
  std::istringstream in(read_file(path));
  std::string line;
  std::getline(in, line);
  int row = 1;
  while (std::getline(in, line)) {
    ++row;
    if (line.empty()) continue;
    std::istringstream fields(line);
    std::string field;
    for (std::size_t c = 0; c < columns; ++c) {
      if (!std::getline(fields, field, ',')) {
        throw Error(path.string() + ":" + std::to_string(row) + ": expected " +
                    std::to_string(columns) + " columns");
      }
      try {
        out[c].push_back(std::stod(field));
      } catch (const std::exception&) {
        throw Error(path.string() + ":" + std::to_string(row) + ": '" + field +
                    "' is not a number");
      }
    }
  }
  return out;
}

// Centred moving average over `window` points (shorter at the ends).
std::vector<double> smooth(const std::vector<double>& v, int window) {
  std::vector<double> out(v.size());
  const int half = window / 2, n = static_cast<int>(v.size());
  for (int i = 0; i < n; ++i) {
    const int lo = std::max(0, i - half), hi = std::min(n - 1, i + half);
    double sum = 0;
    for (int j = lo; j <= hi; ++j) sum += v[j];
    out[i] = sum / (hi - lo + 1);
  }
  return out;
}

}  // namespace

void draw_training_curves(const fs::path& run_dir) {
  // step, learning_rate, loss, centre, keypoint_heatmap, keypoint_regression, keypoint_offset,
  // box_scale, box_offset, distill, images_per_second
  const auto train = read_columns(run_dir / "train_log.csv", 11);
  const fs::path val_path = run_dir / "val_log.csv";
  std::vector<std::vector<double>> val;
  if (fs::exists(val_path)) val = read_columns(val_path, 6);
  const bool has_val = !val.empty() && !val[0].empty();
  const std::vector<double>& steps = train[0];
  if (steps.empty()) return;
  const int window = std::max(1, static_cast<int>(steps.size()) / 50);
  struct Series {
    int column, colour;
    const char* name;
  };
  const Series series[] = {{2, 1, "total"},      {3, 2, "centre"},      {4, 3, "keypoint heatmaps"},
                           {5, 4, "regression"}, {6, 6, "offsets"},     {7, 7, "box scale"},
                           {8, 5, "box offset"}, {9, 8, "distillation"}};
  // The distillation line only for runs that distil (its column is all zeros otherwise).
  const bool distilled =
      std::any_of(train[9].begin(), train[9].end(), [](double v) { return v != 0; });
  const std::size_t shown = std::size(series) - (distilled ? 0 : 1);
  std::vector<std::vector<double>> smoothed;
  double top = 0;
  for (std::size_t i = 0; i < shown; ++i) {
    smoothed.push_back(smooth(train[series[i].column], window));
    for (double v : smoothed.back()) top = std::max(top, v);
  }
  const double last_step = std::max(1.0, steps.back());
  plot::render(run_dir / "curves", has_val ? 1400 : 700, 480, has_val ? 2 : 1, 1, [&] {
    plot::panel(0, last_step, 0, top > 0 ? top * 1.05 : 1, "step",
                "loss (moving average of " + std::to_string(window) + ")", "training loss");
    for (std::size_t i = 0; i < smoothed.size(); ++i) {
      plot::line(steps, smoothed[i], series[i].colour);
      plot::legend_entry(static_cast<int>(i), series[i].colour, series[i].name);
    }
    if (!has_val) return;
    double ap_top = 0;
    for (int c : {1, 4}) {
      for (double v : val[c]) ap_top = std::max(ap_top, v);
    }
    plot::panel(0, last_step, 0, std::max(0.05, ap_top * 1.4), "step", "AP",
                "validation (predict + eval)");
    plot::line(val[0], val[1], 2);
    plot::line(val[0], val[4], 3);
    plot::legend_entry(0, 2, "keypoint AP");
    plot::legend_entry(1, 3, "box AP");
  });
}

}  // namespace wheelpose::learn
