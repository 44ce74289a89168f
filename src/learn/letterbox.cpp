#include "learn/letterbox.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "core/error.h"

namespace wheelpose::learn {

Letterbox plan_letterbox(int width, int height, int longer_side) {
  WHEELPOSE_CHECK(width > 0 && height > 0 && longer_side > 0 && longer_side % 32 == 0);
  Letterbox b;
  b.scale = static_cast<double>(longer_side) / std::max(width, height);
  b.resized_w = std::clamp(static_cast<int>(std::lround(width * b.scale)), 1, longer_side);
  b.resized_h = std::clamp(static_cast<int>(std::lround(height * b.scale)), 1, longer_side);
  b.input_w = (b.resized_w + 31) / 32 * 32;
  b.input_h = (b.resized_h + 31) / 32 * 32;
  return b;
}

cv::Mat letterbox_image(const cv::Mat& rgb, const Letterbox& box) {
  cv::Mat input(box.input_h, box.input_w, CV_8UC3, cv::Scalar::all(0));
  cv::Mat inside = input(cv::Rect(0, 0, box.resized_w, box.resized_h));
  const bool shrinking = box.resized_w < rgb.cols;
  cv::resize(rgb, inside, inside.size(), 0, 0, shrinking ? cv::INTER_AREA : cv::INTER_LINEAR);
  return input;
}

cv::Point2d letterbox_to_image(const Letterbox& box, double y_fraction, double x_fraction) {
  return {x_fraction * box.input_w / box.scale, y_fraction * box.input_h / box.scale};
}

SquareCrop square_around(const coco::Box& box, double margin) {
  const double side = std::max({box.w, box.h, 1.0}) * margin;
  return {box.x + box.w / 2 - side / 2, box.y + box.h / 2 - side / 2, side};
}

cv::Mat crop_image(const cv::Mat& rgb, const SquareCrop& crop, int size) {
  // Maps crop pixel centres onto image pixel centres: x_img = x0 + (u + 0.5)·s − 0.5.
  const double s = crop.side / size;
  const cv::Matx23d to_image(s, 0, crop.x0 + 0.5 * s - 0.5, 0, s, crop.y0 + 0.5 * s - 0.5);
  cv::Mat out;
  cv::warpAffine(rgb, out, to_image, cv::Size(size, size), cv::INTER_LINEAR | cv::WARP_INVERSE_MAP,
                 cv::BORDER_CONSTANT, cv::Scalar::all(0));
  return out;
}

cv::Point2d crop_to_image(const SquareCrop& crop, double y_fraction, double x_fraction) {
  return {crop.x0 + x_fraction * crop.side, crop.y0 + y_fraction * crop.side};
}

}  // namespace wheelpose::learn
