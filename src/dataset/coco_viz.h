#pragma once
// Overlays of COCO annotations on their images: masks (polygons), boxes, skeletons; keypoints
// drawn as in the paper's figures — visible (v=2) with a white outline, occluded (v=1) with a
// black one — and a contact sheet of all overlays.

#include <cstdint>
#include <filesystem>
#include <opencv2/core.hpp>
#include <string>

#include "dataset/coco_file.h"

namespace wheelpose::dataset {

// A grid of `count` cells of `cell` size, as square as possible, filled row by row: each image
// is scaled to fit its cell, keeping its aspect ratio, and centred on a dark background.
class ContactSheet {
 public:
  ContactSheet(std::size_t count, cv::Size cell);
  void place(std::size_t index, const cv::Mat& image);  // 8-bit, 3 channels
  const cv::Mat& image() const { return sheet_; }

 private:
  cv::Size cell_;
  int cols_;
  cv::Mat sheet_;
};

// Draws the first `n` images by id into out_dir/<file stem>.png and out_dir/contact_sheet.png;
// with `overlays` false the images are copied as they are (a contact sheet of the frames
// themselves). Returns the number of images drawn. A missing or unreadable image is an error
// naming it.
std::size_t visualize_coco(const json& root, const std::string& source,
                           const std::filesystem::path& images_dir,
                           const std::filesystem::path& out_dir, std::int64_t n,
                           bool overlays = true);

}  // namespace wheelpose::dataset
