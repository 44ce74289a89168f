#pragma once
// Motion blur of a rendered image from its per-pixel motion (FrameBuffers::motion): each pixel
// gathers the surfaces that cross it while the shutter is open, the reconstruction filter of
// McGuire et al. (2012, "A Reconstruction Filter for Plausible Motion Blur"). A moving person
// smears over the still background behind it, and the background shows through the edges of
// the moving person; still pixels away from anything moving are left exactly as they were.

#include <opencv2/core.hpp>

namespace wheelpose::render {

// Longest blur streak, in pixels (motion beyond it is shortened to it).
inline constexpr float kMaxMotionBlurPixels = 64.0f;

// linear: CV_32FC3; depth: CV_32F metres (0 = no hit, far away); motion: CV_32FC2 pixels over
// the open shutter, centred on the image's instant (an empty matrix returns a copy of
// `linear`). Every pixel is a pure function of its inputs, so threads do not change the result.
cv::Mat motion_blur(const cv::Mat& linear, const cv::Mat& depth, const cv::Mat& motion);

}  // namespace wheelpose::render
