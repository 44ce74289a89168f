#include "learn/letterbox.h"

#include <gtest/gtest.h>

namespace wheelpose::learn {
namespace {

TEST(Letterbox, AWideFrameKeepsItsAspectAndPadsToThe32Grid) {
  const Letterbox b = plan_letterbox(1280, 720, 512);
  EXPECT_DOUBLE_EQ(b.scale, 0.4);
  EXPECT_EQ(b.resized_w, 512);
  EXPECT_EQ(b.resized_h, 288);
  EXPECT_EQ(b.input_w, 512);
  EXPECT_EQ(b.input_h, 288);
  const Letterbox odd = plan_letterbox(640, 427, 256);  // 170.8 rows round to 171, pad to 192
  EXPECT_EQ(odd.resized_h, 171);
  EXPECT_EQ(odd.input_h, 192);
}

TEST(Letterbox, MapsInputFractionsBackToImagePixels) {
  const Letterbox b = plan_letterbox(1280, 720, 512);
  const cv::Point2d far_corner = letterbox_to_image(b, 1.0, 1.0);
  EXPECT_NEAR(far_corner.x, 1280, 1e-9);
  EXPECT_NEAR(far_corner.y, 720, 1e-9);
  const Letterbox padded = plan_letterbox(640, 427, 256);  // input 256 × 192
  EXPECT_NEAR(letterbox_to_image(padded, 0.5, 0.25).y, 96 / 0.4, 1e-9);
  EXPECT_NEAR(letterbox_to_image(padded, 0.5, 0.25).x, 64 / 0.4, 1e-9);
}

TEST(Letterbox, TheImageSitsTopLeftOnBlack) {
  cv::Mat rgb(90, 200, CV_8UC3, cv::Scalar(10, 20, 30));
  const Letterbox b = plan_letterbox(200, 90, 64);  // 64 × 28.8 → 29 rows, padded to 32
  const cv::Mat in = letterbox_image(rgb, b);
  ASSERT_EQ(in.cols, 64);
  ASSERT_EQ(in.rows, 32);
  EXPECT_EQ(in.at<cv::Vec3b>(0, 0), cv::Vec3b(10, 20, 30));
  EXPECT_EQ(in.at<cv::Vec3b>(28, 63), cv::Vec3b(10, 20, 30));
  EXPECT_EQ(in.at<cv::Vec3b>(29, 0), cv::Vec3b(0, 0, 0));
}

TEST(Letterbox, SquareCropsAreCentredOnTheBoxAndMapBack) {
  const SquareCrop c = square_around({100, 50, 40, 80}, 1.25);
  EXPECT_DOUBLE_EQ(c.side, 100);
  EXPECT_DOUBLE_EQ(c.x0, 70);
  EXPECT_DOUBLE_EQ(c.y0, 40);
  const cv::Point2d centre = crop_to_image(c, 0.5, 0.5);
  EXPECT_DOUBLE_EQ(centre.x, 120);
  EXPECT_DOUBLE_EQ(centre.y, 90);
  // A marked pixel lands where the mapping says.
  cv::Mat rgb(200, 300, CV_8UC3, cv::Scalar::all(0));
  rgb.at<cv::Vec3b>(90, 120) = cv::Vec3b(255, 255, 255);
  const cv::Mat crop = crop_image(rgb, {70, 40, 100}, 100);
  EXPECT_EQ(crop.at<cv::Vec3b>(50, 50), cv::Vec3b(255, 255, 255));
  EXPECT_EQ(crop.at<cv::Vec3b>(0, 0), cv::Vec3b(0, 0, 0));
}

}  // namespace
}  // namespace wheelpose::learn
