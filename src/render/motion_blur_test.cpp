#include "render/motion_blur.h"

#include <gtest/gtest.h>

#include <opencv2/core.hpp>

namespace wheelpose::render {
namespace {

constexpr int kWidth = 80, kHeight = 40;

// A white 10×10 square at depth 2 m in front of a dark wall at 5 m; the square moves by
// `travel` pixels over the shutter, the wall stands still.
struct MovingSquare {
  cv::Mat linear{kHeight, kWidth, CV_32FC3, cv::Scalar::all(0.1)};
  cv::Mat depth{kHeight, kWidth, CV_32F, cv::Scalar(5.0f)};
  cv::Mat motion{kHeight, kWidth, CV_32FC2, cv::Scalar::all(0)};
  explicit MovingSquare(cv::Vec2f travel) {
    const cv::Rect square(35, 15, 10, 10);
    linear(square).setTo(cv::Scalar::all(1.0));
    depth(square).setTo(cv::Scalar(2.0f));
    motion(square).setTo(cv::Scalar(travel[0], travel[1]));
  }
};

float red(const cv::Mat& m, int x, int y) { return m.at<cv::Vec3f>(y, x)[0]; }

TEST(MotionBlur, NothingMovingLeavesTheImageAlone) {
  MovingSquare still({0, 0});
  EXPECT_EQ(
      cv::norm(motion_blur(still.linear, still.depth, still.motion), still.linear, cv::NORM_INF),
      0);
  EXPECT_EQ(cv::norm(motion_blur(still.linear, still.depth, cv::Mat()), still.linear, cv::NORM_INF),
            0);
}

TEST(MotionBlur, AMovingSquareSmearsAlongItsMotionOnly) {
  MovingSquare scene({16, 0});  // 8 px either side of the labelled instant
  const cv::Mat out = motion_blur(scene.linear, scene.depth, scene.motion);
  // The wall beside the square along the motion catches the streak, fading with distance.
  EXPECT_GT(red(out, 34, 20), 0.3f);
  EXPECT_GT(red(out, 34, 20), red(out, 38 - 8, 20));
  EXPECT_GT(red(out, 38 - 8, 20), 0.1f + 1e-3f);
  EXPECT_GT(red(out, 45, 20), 0.3f);
  // Beyond the streak's reach and above or below the square, the wall is untouched.
  EXPECT_EQ(red(out, 35 - 9, 20), 0.1f);
  EXPECT_EQ(red(out, 44 + 9, 20), 0.1f);
  EXPECT_EQ(red(out, 40, 14), 0.1f);
  EXPECT_EQ(red(out, 40, 25), 0.1f);
  // The wall shows through the square's leading and trailing edges; its middle stays bright.
  EXPECT_LT(red(out, 35, 20), 1.0f);
  EXPECT_LT(red(out, 44, 20), 1.0f);
  EXPECT_GT(red(out, 40, 20), red(out, 35, 20));
  // Left and right are mirror images: the streak is centred on the instant.
  for (int d = 0; d < 12; ++d) EXPECT_NEAR(red(out, 35 - d, 18), red(out, 44 + d, 18), 1e-5f);
}

TEST(MotionBlur, AStillSurfaceInFrontHidesAStreakBehindIt) {
  MovingSquare scene({16, 0});
  // A still post at 1 m, nearer than the square, right beside it.
  const cv::Rect post(30, 0, 4, kHeight);
  scene.linear(post).setTo(cv::Scalar::all(0.5));
  scene.depth(post).setTo(cv::Scalar(1.0f));
  const cv::Mat out = motion_blur(scene.linear, scene.depth, scene.motion);
  for (int y = 0; y < kHeight; ++y) EXPECT_EQ(red(out, 32, y), 0.5f) << y;
}

TEST(MotionBlur, StreaksLongerThanTheCapAreShortened) {
  MovingSquare fast({400, 0});
  const cv::Mat out = motion_blur(fast.linear, fast.depth, fast.motion);
  const int reach = static_cast<int>(kMaxMotionBlurPixels / 2);
  EXPECT_GT(red(out, 35 - reach + 4, 20), 0.1f);
  EXPECT_EQ(red(out, 35 - reach - 2, 20), 0.1f);
}

TEST(MotionBlur, SameResultWhateverTheThreadCount) {
  MovingSquare scene({9, -5});
  const int threads = cv::getNumThreads();
  cv::setNumThreads(1);
  const cv::Mat one = motion_blur(scene.linear, scene.depth, scene.motion);
  cv::setNumThreads(4);
  const cv::Mat four = motion_blur(scene.linear, scene.depth, scene.motion);
  cv::setNumThreads(threads);
  EXPECT_EQ(cv::norm(one, four, cv::NORM_INF), 0);
}

}  // namespace
}  // namespace wheelpose::render
