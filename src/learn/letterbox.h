#pragma once
// Fitting images to a network's input and mapping its normalised outputs back to pixels.
// Multi-person models see the whole image, scaled so its longer side is the input size and
// padded on the right and bottom to multiples of 32 (the models' stride), so a 1280×720 frame at
// 512 becomes 512×288, not a square with 40 % padding. Single-person models see a square crop
// around a person's box.

#include <opencv2/core.hpp>

#include "core/coco_data.h"

namespace wheelpose::learn {

struct Letterbox {
  double scale = 1;                  // input pixels per image pixel
  int resized_w = 0, resized_h = 0;  // the image inside the input
  int input_w = 0, input_h = 0;      // multiples of 32
};

// `longer_side` must be a positive multiple of 32; the image `width` × `height` positive.
Letterbox plan_letterbox(int width, int height, int longer_side);

// `rgb` (CV_8UC3) scaled (area filter when shrinking, bilinear when enlarging) into the top
// left of a black input_h × input_w image.
cv::Mat letterbox_image(const cv::Mat& rgb, const Letterbox& box);

// A point given as fractions of the network input's height and width, in image pixels.
cv::Point2d letterbox_to_image(const Letterbox& box, double y_fraction, double x_fraction);

// A square around a person box: its centre, the longer side × `margin`.
struct SquareCrop {
  double x0 = 0, y0 = 0, side = 1;
};
SquareCrop square_around(const coco::Box& box, double margin = 1.25);

// The crop scaled to size × size (bilinear), black outside the image.
cv::Mat crop_image(const cv::Mat& rgb, const SquareCrop& crop, int size);

// A point given as fractions of the crop's height and width, in image pixels.
cv::Point2d crop_to_image(const SquareCrop& crop, double y_fraction, double x_fraction);

}  // namespace wheelpose::learn
