#include "learn/train_data.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/error.h"

namespace wheelpose::learn {
namespace {

namespace fs = std::filesystem;

// A 320×240 black image with one white 3×3 dot per labelled keypoint of a single person.
struct DotScene {
  cv::Mat rgb = cv::Mat::zeros(240, 320, CV_8UC3);
  TrainPerson person;
  DotScene() {
    person.box = {100, 60, 80, 120};
    for (int k = 0; k < 17; ++k) {
      const double x = 110 + 3.5 * k, y = 70 + 6.0 * k;
      person.keypoints[3 * k] = x;
      person.keypoints[3 * k + 1] = y;
      person.keypoints[3 * k + 2] = k == 3 ? 0 : 2;  // one unlabelled keypoint
      if (k != 3) cv::circle(rgb, cv::Point(int(x), int(y)), 1, cv::Scalar(255, 255, 255), -1);
    }
  }
};

AugmentOptions geometry_only() {
  AugmentOptions o;
  o.input_size = 128;
  o.target_longer_side = 320;  // base scale 1
  o.color_jitter = 0;
  o.blur_probability = 0;
  o.jpeg_probability = 0;
  return o;
}

// --people-size: whatever the frame's scale, the person's longer box side in the input is drawn
// log-uniformly from [min, max] — small and large people both appear.
TEST(Augment, PeopleSizeSetsThePersonsSizeInTheInput) {
  const DotScene scene;
  AugmentOptions o = geometry_only();
  o.input_size = 160;
  o.shift_fraction = 0;
  o.rotate_degrees = 0;
  o.person_size_min = 30;
  o.person_size_max = 150;
  int small = 0, large = 0;
  for (std::uint64_t key = 0; key < 40; ++key) {
    const TrainSample s = augment(scene.rgb, {scene.person}, {}, o, 5, key);
    ASSERT_EQ(s.people.size(), 1u);
    const double side = std::max(s.people[0].box.w, s.people[0].box.h);
    EXPECT_GE(side, 30 - 1e-9);
    EXPECT_LE(side, 150 + 1e-9);
    EXPECT_NEAR(s.people[0].box.w / s.people[0].box.h, 80.0 / 120.0, 1e-9);
    small += side < 60;
    large += side > 100;
  }
  EXPECT_GE(small, 5);
  EXPECT_GE(large, 5);
}

// Without rotation a box keeps its exact size (scale 1 here) and stays centred on the person;
// with rotation it grows only by the rotated inscribed ellipse (≤ 15°: at most w cos + h sin of
// the ellipse's half-axes, under the rotated corners' w cos + h sin of the full box).
TEST(Augment, BoxesStayTightUnderRotation) {
  const DotScene scene;
  AugmentOptions o = geometry_only();
  o.input_size = 160;
  o.shift_fraction = 0;
  o.scale_min = o.scale_max = 1;
  o.rotate_degrees = 0;
  for (std::uint64_t key = 0; key < 5; ++key) {
    const TrainSample s = augment(scene.rgb, {scene.person}, {}, o, 3, key);
    ASSERT_EQ(s.people.size(), 1u);
    EXPECT_NEAR(s.people[0].box.w, 80, 1e-9);
    EXPECT_NEAR(s.people[0].box.h, 120, 1e-9);
    EXPECT_NEAR(s.people[0].box.x + s.people[0].box.w / 2, 80, 1e-9);
    EXPECT_NEAR(s.people[0].box.y + s.people[0].box.h / 2, 80, 1e-9);
  }
  o.rotate_degrees = 15;
  const double t = 15 * 3.14159265358979 / 180;
  for (std::uint64_t key = 0; key < 20; ++key) {
    const TrainSample s = augment(scene.rgb, {scene.person}, {}, o, 3, key);
    ASSERT_EQ(s.people.size(), 1u);
    EXPECT_LE(s.people[0].box.w, std::hypot(80 * std::cos(t), 120 * std::sin(t)) + 1e-9);
    EXPECT_GE(s.people[0].box.w, 80 - 1e-9);
    EXPECT_LE(s.people[0].box.h, 120 + 1e-9);
    EXPECT_NEAR(s.people[0].box.x + s.people[0].box.w / 2, 80, 1e-9);
  }
}

// The keypoints travel with the pixels: after any scale, rotation, shift and flip the image is
// bright where a labelled keypoint is said to be.
TEST(Augment, KeypointsFollowThePixels) {
  const DotScene scene;
  int checked = 0;
  for (std::uint64_t key = 0; key < 20; ++key) {
    const TrainSample s = augment(scene.rgb, {scene.person}, {}, geometry_only(), 7, key);
    ASSERT_EQ(s.rgb.rows, 128);
    ASSERT_EQ(s.people.size(), 1u);
    for (int k = 0; k < 17; ++k) {
      if (s.people[0].keypoints[3 * k + 2] == 0) continue;
      const int x = static_cast<int>(std::lround(s.people[0].keypoints[3 * k]));
      const int y = static_cast<int>(std::lround(s.people[0].keypoints[3 * k + 1]));
      if (x < 1 || y < 1 || x > 126 || y > 126) continue;
      double best = 0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          best = std::max(best, double(s.rgb.at<cv::Vec3b>(y + dy, x + dx)[0]));
      EXPECT_GT(best, 60) << "key " << key << " keypoint " << k;
      ++checked;
    }
    EXPECT_EQ(s.people[0].keypoints[3 * 3 + 2], 0);  // unlabelled stays unlabelled
  }
  EXPECT_GT(checked, 150);
}

// Labels and pixels agree to a tenth of a pixel, shrunk (through an area filter) or enlarged,
// mirrored or not: one bright pixel's centre (its centroid in the input) is where its label
// lands. COCO's coordinates put pixel i's centre at i + 0.5; OpenCV's warp at i.
TEST(Augment, LabelsSitOnTheirPixelsToATenthOfAPixel) {
  cv::Mat rgb = cv::Mat::zeros(200, 300, CV_8UC3);
  rgb(cv::Rect(140, 90, 10, 10)).setTo(cv::Scalar(255, 255, 255));  // continuous centre 145, 95
  TrainPerson person;
  person.box = {120, 70, 50, 50};
  person.keypoints[0] = 145, person.keypoints[1] = 95, person.keypoints[2] = 2;
  AugmentOptions o = geometry_only();
  o.rotate_degrees = 0;
  int checked = 0;
  for (const double side : {120.0, 300.0, 640.0}) {  // scales 0.4, 1 and about 2.1
    o.target_longer_side = static_cast<int>(side);
    o.scale_min = o.scale_max = 1;
    for (std::uint64_t key = 0; key < 8; ++key) {
      const TrainSample s = augment(rgb, {person}, {}, o, 3, key);
      ASSERT_EQ(s.people.size(), 1u);
      cv::Mat grey;
      cv::cvtColor(s.rgb, grey, cv::COLOR_RGB2GRAY);
      const cv::Moments mo = cv::moments(grey);
      ASSERT_GT(mo.m00, 0) << side << " " << key;
      const double cx = mo.m10 / mo.m00 + 0.5, cy = mo.m01 / mo.m00 + 0.5;
      EXPECT_NEAR(cx, s.people[0].keypoints[0], 0.1) << "side " << side << " key " << key;
      EXPECT_NEAR(cy, s.people[0].keypoints[1], 0.1) << "side " << side << " key " << key;
      ++checked;
    }
  }
  EXPECT_EQ(checked, 24);
}

// With a flip, a left/right pair trades places: left_eye (1) gets what was right_eye (2).
TEST(Augment, FlipSwapsLeftAndRight) {
  const DotScene scene;
  AugmentOptions o = geometry_only();
  o.rotate_degrees = 0;
  int compared = 0;
  for (std::uint64_t key = 0; key < 10; ++key) {
    o.flip_probability = 1;
    const TrainSample flipped = augment(scene.rgb, {scene.person}, {{1, 2}}, o, 3, key);
    o.flip_probability = 0;
    const TrainSample kept = augment(scene.rgb, {scene.person}, {{1, 2}}, o, 3, key);
    ASSERT_EQ(flipped.people.size(), 1u);
    if (kept.people[0].keypoints[3 * 2 + 2] == 0) continue;  // shifted out of the input
    // Same draws apart from the mirror: x' = size - x; keypoint 1 of the flip is keypoint 2's.
    EXPECT_NEAR(flipped.people[0].keypoints[3 * 1], 128 - kept.people[0].keypoints[3 * 2], 1e-6);
    EXPECT_NEAR(flipped.people[0].keypoints[3 * 1 + 1], kept.people[0].keypoints[3 * 2 + 1], 1e-6);
    ++compared;
  }
  EXPECT_GT(compared, 3);
}

TEST(Augment, SameSeedAndKeyGiveTheSameSample) {
  const DotScene scene;
  const AugmentOptions o;  // every augmentation on
  const TrainSample a = augment(scene.rgb, {scene.person}, {{1, 2}}, o, 11, 5);
  const TrainSample b = augment(scene.rgb, {scene.person}, {{1, 2}}, o, 11, 5);
  const TrainSample c = augment(scene.rgb, {scene.person}, {{1, 2}}, o, 11, 6);
  EXPECT_EQ(cv::norm(a.rgb, b.rgb, cv::NORM_INF), 0);
  EXPECT_EQ(a.people[0].keypoints, b.people[0].keypoints);
  EXPECT_NE(a.people[0].keypoints, c.people[0].keypoints);
}

// A crowd region rides along through the transform as a box that never shrinks, and the crop
// always centres on the person, whatever the draw.
TEST(Augment, CrowdRegionsFollowTheCropButAreNeverItsCentre) {
  const DotScene scene;
  TrainPerson crowd;
  crowd.box = {0, 0, 320, 50};  // a band across the top of the image
  crowd.ignore = true;
  AugmentOptions o = geometry_only();
  o.rotate_degrees = 20;
  int crowds_seen = 0;
  for (std::uint64_t key = 0; key < 20; ++key) {
    const TrainSample with = augment(scene.rgb, {crowd, scene.person}, {}, o, 7, key);
    const TrainSample without = augment(scene.rgb, {scene.person}, {}, o, 7, key);
    // The same crop as without the region: the region is never the anchor and draws nothing.
    EXPECT_EQ(cv::norm(with.rgb, without.rgb, cv::NORM_L1), 0.0) << key;
    int people = 0;
    for (const TrainPerson& p : with.people) {
      if (!p.ignore) {
        ++people;
        continue;
      }
      ++crowds_seen;
      EXPECT_GE(p.box.w, 1);
      for (int k = 0; k < 17; ++k)
        EXPECT_EQ(p.keypoints[3 * k + 2], 0) << "a region has no keypoints";
    }
    EXPECT_EQ(people, 1) << key;
  }
  EXPECT_GT(crowds_seen, 0);  // the band is in view in some crops
}

TEST(TrainSource, WeightAfterTheLastColon) {
  EXPECT_EQ(parse_train_source("a/b.json").coco, "a/b.json");
  EXPECT_EQ(parse_train_source("a/b.json:2.5").weight, 2.5);
  EXPECT_EQ(parse_train_source("a/b.json:2.5").coco, "a/b.json");
  EXPECT_THROW(parse_train_source("a.json:0"), Error);
  EXPECT_THROW(parse_train_source("a.json:x"), Error);
}

TEST(PickImage, FollowsTheWeights) {
  const std::vector<double> cumulative = {1, 4};  // image 1 three times as likely
  int ones = 0;
  for (int step = 0; step < 4000; ++step) ones += pick_image(cumulative, 1, step, 0) == 1;
  EXPECT_NEAR(ones / 4000.0, 0.75, 0.03);
  EXPECT_EQ(pick_image(cumulative, 1, 17, 3), pick_image(cumulative, 1, 17, 3));
}

TEST(TrainSet, MissingImageAndNoKeypointsAreOneLineErrors) {
  const fs::path dir = fs::temp_directory_path() / "wheelpose_train_data_test";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string no_kp =
      R"({"images":[{"id":1,"file_name":"a.png"}],"annotations":[{"id":1,"image_id":1,)"
      R"("category_id":1,"bbox":[1,1,5,5],"area":25,"iscrowd":0}],)"
      R"("categories":[{"id":1,"name":"person"}]})";
  std::ofstream(dir / "gt.json") << no_kp;
  try {
    load_train_set({{dir / "gt.json", 1}});
    FAIL() << "a missing image must throw";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("a.png"), std::string::npos) << e.what();
  }
  cv::imwrite((dir / "a.png").string(), cv::Mat::zeros(8, 8, CV_8UC3));
  try {
    load_train_set({{dir / "gt.json", 1}});
    FAIL() << "no labelled keypoint must throw";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no person with a labelled keypoint"), std::string::npos)
        << e.what();
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace wheelpose::learn
