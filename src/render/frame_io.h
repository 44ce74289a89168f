#pragma once
// PNG encoding and atomic writing of frame buffers:
//   rgb.png       8-bit sRGB colour
//   depth.png     16-bit grey, millimetres along the view axis (0 = no hit, saturates at 65535)
//   normals.png   16-bit RGB, camera-space unit normal n stored as round((n + 1) / 2 · 65535),
//                 (0, 0, 0) where nothing was hit
//   instance.png  16-bit grey instance ids; semantic.png 16-bit grey semantic class ids

#include <cstdint>
#include <filesystem>
#include <opencv2/core.hpp>
#include <string>
#include <utility>
#include <vector>

#include "render/renderer.h"

namespace wheelpose::render {

cv::Mat depth_to_millimetres(const cv::Mat& depth);  // CV_32F metres → CV_16U
cv::Mat normals_to_u16(const cv::Mat& normals);      // CV_32FC3 → CV_16UC3 (RGB order)

// PNG bytes of an RGB (8- or 16-bit, 1 or 3 channels) image.
std::vector<std::uint8_t> encode_png(const cv::Mat& image_rgb);

// The five PNGs of a frame, as (file name, bytes) in the order listed above; encoded in parallel.
std::vector<std::pair<std::string, std::vector<std::uint8_t>>> encode_frame(
    const FrameBuffers& frame);

// Timing of write_frame: encoding and writing (ms).
struct WriteTimings {
  double encode_ms = 0;
  double write_ms = 0;
};

// Writes the five PNGs into `dir` (created if needed), each file atomically.
WriteTimings write_frame(const FrameBuffers& frame, const std::filesystem::path& dir);

}  // namespace wheelpose::render
