#include "dataset/plot.h"

#include <plplot/plplot.h>

#include <algorithm>
#include <mutex>

#include "core/atomic_file.h"
#include "core/error.h"

namespace wheelpose::dataset::plot {
namespace {

namespace fs = std::filesystem;

void set_palette() {
  plscmap0n(9);
  plscol0(0, 255, 255, 255);
  plscol0(1, 0, 0, 0);
  plscol0(2, 0, 114, 178);
  plscol0(3, 230, 159, 0);
  plscol0(4, 213, 0, 0);
  plscol0(5, 128, 128, 128);
  plscol0(6, 0, 158, 115);
  plscol0(7, 204, 121, 167);
  plscol0(8, 86, 180, 233);
  // Colour map 1 (heatmaps): white -> blue -> dark red, in RGB.
  PLFLT pos[] = {0.0, 0.35, 0.7, 1.0};
  PLFLT r[] = {1.0, 0.35, 0.9, 0.5}, g[] = {1.0, 0.55, 0.3, 0.0}, b[] = {1.0, 0.9, 0.1, 0.0};
  plscmap1l(1, 4, pos, r, g, b, nullptr);
}

}  // namespace

void render(const fs::path& base, int width, int height, int nx, int ny,
            const std::function<void()>& draw) {
  static std::mutex plplot_state;
  const std::lock_guard<std::mutex> lock(plplot_state);
  const std::pair<const char*, const char*> devices[] = {{"pngcairo", ".png"},
                                                         {"svgcairo", ".svg"}};
  for (const auto& [device, ext] : devices) {
    fs::path tmp = base;
    tmp += std::string(ext) + ".tmp";
    fs::path final_path = base;
    final_path += ext;
    plsdev(device);
    plsfnam(tmp.c_str());
    plspage(0, 0, width, height, 0, 0);
    set_palette();
    plssub(nx, ny);
    plinit();
    plschr(0, 0.8);
    draw();
    plend();
    std::error_code ec;
    if (!fs::exists(tmp, ec)) {
      throw Error(final_path.string() + ": PLplot did not write the figure", ErrorKind::kFailure);
    }
    const std::string bytes = read_file(tmp);
    fs::remove(tmp, ec);
    write_file_atomic(final_path, bytes);
  }
}

void panel(double xmin, double xmax, double ymin, double ymax, const std::string& x_label,
           const std::string& y_label, const std::string& title) {
  pladv(0);
  plvsta();
  plwind(xmin, xmax, ymin, ymax);
  plcol0(1);
  plbox("bcnst", 0, 0, "bcnstv", 0, 0);
  pllab(x_label.c_str(), y_label.c_str(), title.c_str());
}

void bar(double x0, double x1, double y, int colour) {
  PLFLT xs[] = {x0, x1, x1, x0}, ys[] = {0, 0, y, y};
  plcol0(colour);
  plfill(4, xs, ys);
  plcol0(1);
  PLFLT lx[] = {x0, x0, x1, x1}, ly[] = {0, y, y, 0};
  plline(4, lx, ly);
}

void line(const std::vector<double>& xs, const std::vector<double>& ys, int colour) {
  const int n = static_cast<int>(std::min(xs.size(), ys.size()));
  if (n < 2) return;
  std::vector<PLFLT> x(xs.begin(), xs.begin() + n), y(ys.begin(), ys.begin() + n);
  plcol0(colour);
  plline(n, x.data(), y.data());
  plcol0(1);
}

void legend_entry(int row, int colour, const std::string& text) {
  // Normalised viewport coordinates: rows of 6 % height from the top left corner.
  PLFLT xmin, xmax, ymin, ymax;
  plgvpw(&xmin, &xmax, &ymin, &ymax);
  const double y = ymax - (ymax - ymin) * (0.07 + 0.06 * row);
  const double x0 = xmin + (xmax - xmin) * 0.5, x1 = xmin + (xmax - xmin) * 0.57;
  PLFLT lx[] = {x0, x1}, ly[] = {y, y};
  plcol0(colour);
  plline(2, lx, ly);
  plcol0(1);
  plptex(x1 + (xmax - xmin) * 0.01, y, 1, 0, 0, text.c_str());
}

}  // namespace wheelpose::dataset::plot
