#include "render/frame_io.h"

#include <tbb/parallel_invoke.h>

#include <chrono>
#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <span>
#include <utility>

#include "core/atomic_file.h"
#include "core/error.h"

namespace wheelpose::render {

cv::Mat depth_to_millimetres(const cv::Mat& depth) {
  cv::Mat out(depth.size(), CV_16U);
  for (int y = 0; y < depth.rows; ++y) {
    for (int x = 0; x < depth.cols; ++x) {
      const double mm = std::round(static_cast<double>(depth.at<float>(y, x)) * 1000.0);
      out.at<std::uint16_t>(y, x) = static_cast<std::uint16_t>(std::clamp(mm, 0.0, 65535.0));
    }
  }
  return out;
}

cv::Mat normals_to_u16(const cv::Mat& normals) {
  cv::Mat out(normals.size(), CV_16UC3, cv::Scalar::all(0));
  for (int y = 0; y < normals.rows; ++y) {
    for (int x = 0; x < normals.cols; ++x) {
      const cv::Vec3f n = normals.at<cv::Vec3f>(y, x);
      if (n.dot(n) == 0.0f) continue;
      cv::Vec3w& o = out.at<cv::Vec3w>(y, x);
      for (int i = 0; i < 3; ++i) {
        o[i] = static_cast<std::uint16_t>(
            std::lround(std::clamp((n[i] + 1.0f) * 0.5f, 0.0f, 1.0f) * 65535.0f));
      }
    }
  }
  return out;
}

std::vector<std::uint8_t> encode_png(const cv::Mat& image_rgb) {
  cv::Mat bgr = image_rgb;
  if (image_rgb.channels() == 3) cv::cvtColor(image_rgb, bgr, cv::COLOR_RGB2BGR);
  std::vector<std::uint8_t> bytes;
  // Compression 1: PNG size barely changes but encoding is several times faster than the default.
  if (!cv::imencode(".png", bgr, bytes, {cv::IMWRITE_PNG_COMPRESSION, 1})) {
    throw Error("cannot encode a PNG image", ErrorKind::kFailure);
  }
  return bytes;
}

std::vector<std::pair<std::string, std::vector<std::uint8_t>>> encode_frame(
    const FrameBuffers& frame) {
  std::vector<std::pair<std::string, std::vector<std::uint8_t>>> files = {{"rgb.png", {}},
                                                                          {"depth.png", {}},
                                                                          {"normals.png", {}},
                                                                          {"instance.png", {}},
                                                                          {"semantic.png", {}}};
  tbb::parallel_invoke([&] { files[0].second = encode_png(frame.rgb); },
                       [&] { files[1].second = encode_png(depth_to_millimetres(frame.depth)); },
                       [&] { files[2].second = encode_png(normals_to_u16(frame.normals)); },
                       [&] { files[3].second = encode_png(frame.instance); },
                       [&] { files[4].second = encode_png(frame.semantic); });
  return files;
}

WriteTimings write_frame(const FrameBuffers& frame, const std::filesystem::path& dir) {
  using Clock = std::chrono::steady_clock;
  WriteTimings t;
  auto t0 = Clock::now();
  const auto files = encode_frame(frame);
  auto t1 = Clock::now();
  ensure_directory(dir);
  for (const auto& [name, bytes] : files)
    write_file_atomic(dir / name, std::span<const std::uint8_t>(bytes));
  t.encode_ms = std::chrono::duration<double, std::milli>(t1 - t0).count();
  t.write_ms = std::chrono::duration<double, std::milli>(Clock::now() - t1).count();
  return t;
}

}  // namespace wheelpose::render
