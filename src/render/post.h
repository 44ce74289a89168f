#pragma once
// Post-processing of the linear image (see scene::PostProcess for the order and ranges) and the
// final sRGB encoding.

#include <cstdint>
#include <opencv2/core.hpp>

#include "scene/scene.h"

namespace wheelpose::render {

// linear: CV_32FC3 RGB; depth: CV_32F metres (0 = no hit, treated as far); motion: CV_32FC2
// (FrameBuffers::motion; empty = no motion blur). Motion blur comes first (it happens while
// the light is gathered), then the lens and the rest. Returns CV_8UC3 RGB. Film grain is
// seeded per pixel from `seed`, so the result does not depend on threads.
cv::Mat apply_post(const cv::Mat& linear, const cv::Mat& depth, const scene::PostProcess& post,
                   float focus_distance, std::uint64_t seed, const cv::Mat& motion = cv::Mat());

// Post-processing on the linear buffer only (no encoding), for tests and tools. `seed` seeds
// the sensor noise.
cv::Mat apply_post_linear(const cv::Mat& linear, const cv::Mat& depth,
                          const scene::PostProcess& post, float focus_distance,
                          std::uint64_t seed = 0, const cv::Mat& motion = cv::Mat());

// Clamp to [0, 1] and sRGB-encode to 8 bits (CV_8UC3 RGB).
cv::Mat encode_srgb(const cv::Mat& linear);

}  // namespace wheelpose::render
