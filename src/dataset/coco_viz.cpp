#include "dataset/coco_viz.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <unordered_map>
#include <vector>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/image_read.h"

namespace wheelpose::dataset {
namespace {

// A fixed palette so the same file always gives the same pixels.
const cv::Scalar kPalette[] = {{230, 159, 0}, {86, 180, 233}, {0, 158, 115},   {240, 228, 66},
                               {0, 114, 178}, {213, 94, 0},   {204, 121, 167}, {120, 200, 60}};

void write_png(const std::filesystem::path& path, const cv::Mat& image) {
  std::vector<std::uint8_t> bytes;
  if (!cv::imencode(".png", image, bytes)) {
    throw Error(path.string() + ": PNG encoding failed", ErrorKind::kFailure);
  }
  write_file_atomic(path, std::span<const std::uint8_t>(bytes));
}

void draw_annotation(cv::Mat& canvas, const json& a,
                     const std::vector<std::pair<int, int>>& skeleton, const cv::Scalar& colour) {
  const double scale = std::max(1.0, std::max(canvas.cols, canvas.rows) / 640.0);
  const int thick = static_cast<int>(std::lround(2 * scale));
  if (a.contains("segmentation") && a["segmentation"].is_array()) {
    std::vector<std::vector<cv::Point>> polys;
    for (const json& poly : a["segmentation"]) {
      std::vector<cv::Point> pts;
      for (std::size_t i = 0; i + 1 < poly.size(); i += 2) {
        pts.emplace_back(static_cast<int>(std::lround(poly[i].get<double>())),
                         static_cast<int>(std::lround(poly[i + 1].get<double>())));
      }
      polys.push_back(std::move(pts));
    }
    if (!polys.empty()) {
      cv::Mat layer = canvas.clone();
      cv::fillPoly(layer, polys, colour);
      cv::addWeighted(layer, 0.4, canvas, 0.6, 0.0, canvas);
    }
  }
  const json& b = a["bbox"];
  const cv::Point2d p0(b[0].get<double>(), b[1].get<double>());
  const cv::Point2d p1 = p0 + cv::Point2d(b[2].get<double>(), b[3].get<double>());
  cv::rectangle(canvas, cv::Point(p0), cv::Point(p1), colour, thick, cv::LINE_AA);
  if (!a.contains("keypoints")) return;
  const json& kp = a["keypoints"];
  const int nk = static_cast<int>(kp.size() / 3);
  auto point = [&](int k) {
    return cv::Point(static_cast<int>(std::lround(kp[3 * k].get<double>())),
                     static_cast<int>(std::lround(kp[3 * k + 1].get<double>())));
  };
  auto vis = [&](int k) { return k < nk ? static_cast<int>(*as_integer(kp[3 * k + 2])) : 0; };
  for (const auto& [i, j] : skeleton) {
    if (vis(i) > 0 && vis(j) > 0) cv::line(canvas, point(i), point(j), colour, thick, cv::LINE_AA);
  }
  const int radius = static_cast<int>(std::lround(4 * scale));
  for (int k = 0; k < nk; ++k) {
    if (vis(k) == 0) continue;
    cv::circle(canvas, point(k), radius, colour, cv::FILLED, cv::LINE_AA);
    const cv::Scalar outline = vis(k) == 2 ? cv::Scalar(255, 255, 255) : cv::Scalar(0, 0, 0);
    cv::circle(canvas, point(k), radius, outline, std::max(1, thick / 2 + 1), cv::LINE_AA);
  }
}

}  // namespace

ContactSheet::ContactSheet(std::size_t count, cv::Size cell)
    : cell_(cell), cols_(std::max(1, static_cast<int>(std::ceil(std::sqrt(double(count)))))) {
  const int rows = static_cast<int>((count + cols_ - 1) / cols_);
  sheet_ =
      cv::Mat(std::max(1, rows) * cell.height, cols_ * cell.width, CV_8UC3, cv::Scalar(32, 32, 32));
}

void ContactSheet::place(std::size_t index, const cv::Mat& image) {
  const double s = std::min(double(cell_.width) / image.cols, double(cell_.height) / image.rows);
  cv::Mat thumb = image;
  if (s != 1.0) cv::resize(image, thumb, cv::Size(), s, s, cv::INTER_AREA);
  const int x = static_cast<int>(index % cols_) * cell_.width + (cell_.width - thumb.cols) / 2;
  const int y = static_cast<int>(index / cols_) * cell_.height + (cell_.height - thumb.rows) / 2;
  thumb.copyTo(sheet_(cv::Rect(x, y, thumb.cols, thumb.rows)));
}

std::size_t visualize_coco(const json& root, const std::string& source,
                           const std::filesystem::path& images_dir,
                           const std::filesystem::path& out_dir, std::int64_t n, bool overlays) {
  require_usable(root, source);
  if (n < 1) throw Error("coco viz: --n must be >= 1");
  std::unordered_map<std::int64_t, std::vector<std::pair<int, int>>> skeletons;
  for (const json& c : root["categories"]) {
    auto& s = skeletons[*as_integer(c["id"])];
    for (const json& pair : c.value("skeleton", json::array())) {
      s.emplace_back(static_cast<int>(*as_integer(pair[0])) - 1,
                     static_cast<int>(*as_integer(pair[1])) - 1);
    }
  }
  std::vector<const json*> images;
  for (const json& im : root["images"]) images.push_back(&im);
  std::sort(images.begin(), images.end(), [](const json* a, const json* b) {
    return *as_integer((*a)["id"]) < *as_integer((*b)["id"]);
  });
  images.resize(std::min<std::size_t>(images.size(), static_cast<std::size_t>(n)));
  std::unordered_map<std::int64_t, std::vector<const json*>> by_image;
  for (const json& a : root["annotations"]) by_image[*as_integer(a["image_id"])].push_back(&a);

  ensure_directory(out_dir);
  ContactSheet sheet(images.size(), cv::Size(320, 240));
  for (std::size_t i = 0; i < images.size(); ++i) {
    const json& im = *images[i];
    const std::string file = im["file_name"].get<std::string>();
    const std::filesystem::path path = images_dir / file;
    if (!std::filesystem::is_regular_file(path)) {
      throw Error(source + ": image '" + file + "': cannot read " + path.string() +
                  " (no such file)");
    }
    cv::Mat canvas = read_image(path, cv::IMREAD_COLOR);
    auto& anns = by_image[*as_integer(im["id"])];
    std::sort(anns.begin(), anns.end(), [](const json* a, const json* b) {
      return *as_integer((*a)["id"]) < *as_integer((*b)["id"]);
    });
    for (std::size_t k = 0; overlays && k < anns.size(); ++k) {
      draw_annotation(canvas, *anns[k], skeletons[*as_integer((*anns[k])["category_id"])],
                      kPalette[k % std::size(kPalette)]);
    }
    write_png(out_dir / (std::filesystem::path(file).stem().string() + ".png"), canvas);
    sheet.place(i, canvas);
  }
  write_png(out_dir / "contact_sheet.png", sheet.image());
  return images.size();
}

}  // namespace wheelpose::dataset
