#pragma once
// Figures with PLplot (Debian libplplot-dev + plplot-driver-cairo): a packaged C plotting library
// with real axes, labels, histograms and image maps, whose cairo drivers write both PNG
// (pngcairo) and SVG (svgcairo) from the same drawing code, with no display or Python needed.
// PLplot keeps global state, so figures are drawn one at a time (render() holds a lock).
//
// Colour map 0: 0 white background, 1 black ink, 2 blue, 3 orange, 4 red, 5 grey, 6 green,
// 7 purple, 8 sky blue. Colour map 1 (image maps): white -> blue -> dark red.

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace wheelpose::dataset::plot {

// Draws `draw` on an nx × ny grid of panels into base.png and base.svg; each file appears
// atomically. Throws Error when PLplot writes nothing.
void render(const std::filesystem::path& base, int width, int height, int nx, int ny,
            const std::function<void()>& draw);

// Starts the next panel with axes over [xmin, xmax] × [ymin, ymax] and its labels.
void panel(double xmin, double xmax, double ymin, double ymax, const std::string& x_label,
           const std::string& y_label, const std::string& title);

// A filled bar from 0 to y over [x0, x1], outlined in ink.
void bar(double x0, double x1, double y, int colour);

// A polyline through (xs[i], ys[i]).
void line(const std::vector<double>& xs, const std::vector<double>& ys, int colour);

// A legend entry: a short line in `colour` and `text`, at row `row` from the panel's top left.
void legend_entry(int row, int colour, const std::string& text);

}  // namespace wheelpose::dataset::plot
