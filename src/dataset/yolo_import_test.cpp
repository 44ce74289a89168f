#include "dataset/yolo_import.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "core/error.h"

namespace wheelpose::dataset {
namespace {

namespace fs = std::filesystem;

class YoloImport : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("wheelpose_yolo_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    // b.jpg 200×100, a.png 50×40, c.png 10×10 with no label file (a background image).
    cv::imwrite((dir_ / "b.jpg").string(), cv::Mat(100, 200, CV_8UC3, cv::Scalar(0, 0, 0)));
    cv::imwrite((dir_ / "a.png").string(), cv::Mat(40, 50, CV_8UC3, cv::Scalar(9, 9, 9)));
    cv::imwrite((dir_ / "c.png").string(), cv::Mat(10, 10, CV_8UC3, cv::Scalar(9, 9, 9)));
  }
  void TearDown() override { fs::remove_all(dir_); }

  void label(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name) << text;
  }
  json import(const std::string& classes = "1=person,0=crowd,2=drop") {
    YoloImportOptions options;
    options.images_dir = dir_;
    options.classes = parse_yolo_classes(classes);
    return import_yolo(options, load_keypoint_template("coco17"));
  }
  // The Error message of a failing import ("" if it does not fail).
  std::string failure(const std::string& classes = "1=person,0=crowd") {
    try {
      import(classes);
    } catch (const Error& e) {
      return e.what();
    }
    return "";
  }

  fs::path dir_;
};

TEST_F(YoloImport, BoxesBecomePixelBoxesWithTheirRoles) {
  label("b.txt", "1 0.5 0.5 0.2 0.4\n0 0.1 0.2 0.1 0.2\n\n2 0.5 0.5 0.1 0.1\n");
  label("a.txt", "1 0.9 0.5 0.4 1.0\n");  // reaches past the right edge: clipped
  const json root = import();
  ASSERT_EQ(root["images"].size(), 3u);
  EXPECT_EQ(root["images"][0]["file_name"], "a.png");
  EXPECT_EQ(root["images"][0]["width"], 50);
  EXPECT_EQ(root["images"][0]["height"], 40);
  EXPECT_EQ(root["images"][1]["file_name"], "b.jpg");
  EXPECT_EQ(root["images"][2]["file_name"], "c.png");
  ASSERT_EQ(root["annotations"].size(), 3u);  // class 2 dropped, c.png has none

  const json& a = root["annotations"][0];
  EXPECT_EQ(a["image_id"], 1);
  EXPECT_EQ(a["iscrowd"], 0);
  EXPECT_NEAR(a["bbox"][0].get<double>(), 35.0, 1e-9);  // (0.9 - 0.2) × 50
  EXPECT_NEAR(a["bbox"][1].get<double>(), 0.0, 1e-9);
  EXPECT_NEAR(a["bbox"][2].get<double>(), 15.0, 1e-9);  // clipped at x = 50
  EXPECT_NEAR(a["bbox"][3].get<double>(), 40.0, 1e-9);
  EXPECT_NEAR(a["area"].get<double>(), 600.0, 1e-9);

  const json& person = root["annotations"][1];
  EXPECT_EQ(person["id"], 2);
  EXPECT_EQ(person["image_id"], 2);
  EXPECT_EQ(person["iscrowd"], 0);
  EXPECT_EQ(person["yolo_class"], 1);
  EXPECT_NEAR(person["bbox"][0].get<double>(), 80.0, 1e-9);
  EXPECT_NEAR(person["bbox"][1].get<double>(), 30.0, 1e-9);
  EXPECT_NEAR(person["bbox"][2].get<double>(), 40.0, 1e-9);
  EXPECT_NEAR(person["bbox"][3].get<double>(), 40.0, 1e-9);
  EXPECT_EQ(person["num_keypoints"], 0);
  EXPECT_EQ(person["keypoints"].size(), 51u);

  const json& crowd = root["annotations"][2];
  EXPECT_EQ(crowd["iscrowd"], 1);
  EXPECT_EQ(crowd["yolo_class"], 0);
  EXPECT_NEAR(crowd["bbox"][0].get<double>(), 10.0, 1e-9);
  EXPECT_NEAR(crowd["bbox"][3].get<double>(), 20.0, 1e-9);

  EXPECT_EQ(root["categories"][0]["keypoints"].size(), 17u);
  EXPECT_TRUE(validate_coco(root).empty()) << validate_coco(root)[0].message;
}

TEST_F(YoloImport, SwappedRolesScoreTheOtherClass) {
  label("b.txt", "1 0.5 0.5 0.2 0.4\n0 0.1 0.2 0.1 0.2\n");
  const json root = import("0=person,1=crowd");
  EXPECT_EQ(root["annotations"][0]["iscrowd"], 1);
  EXPECT_EQ(root["annotations"][1]["iscrowd"], 0);
}

TEST_F(YoloImport, PoseLinesCarryKeypoints) {
  std::string line = "1 0.5 0.5 0.5 0.5";
  for (int k = 0; k < 17; ++k) line += k == 0 ? " 0.5 0.25 2" : k == 1 ? " 0.1 0.1 1" : " 0 0 0";
  label("b.txt", line + "\n");
  const json root = import();
  const json& a = root["annotations"][0];
  EXPECT_EQ(a["num_keypoints"], 2);
  EXPECT_NEAR(a["keypoints"][0].get<double>(), 100.0, 1e-9);
  EXPECT_NEAR(a["keypoints"][1].get<double>(), 25.0, 1e-9);
  EXPECT_EQ(a["keypoints"][2], 2);
  EXPECT_EQ(a["keypoints"][5], 1);
  EXPECT_EQ(a["keypoints"][8], 0);
}

TEST_F(YoloImport, BadLabelsNameTheFileAndLine) {
  const std::string b = (dir_ / "b.txt").string();
  label("b.txt", "1 0.5 0.5 0.2 0.4\n1 0.5 0.5 0.2\n");
  EXPECT_EQ(failure().rfind(b + ":2: expected 5 values", 0), 0u) << failure();
  label("b.txt", "7 0.5 0.5 0.2 0.4\n");
  EXPECT_EQ(failure(), b + ":1: class 7 is not in the class mapping (0=crowd,1=person)");
  label("b.txt", "1 0.5 1.5 0.2 0.4\n");
  EXPECT_EQ(failure(), b + ":1: value 3 (1.5) is outside [0, 1]");
  label("b.txt", "1 0.5 0.5 -0.2 0.4\n");
  EXPECT_EQ(failure(), b + ":1: value 4 (-0.2) is outside [0, 1]");
  label("b.txt", "1 0.5 0.5 0 0.4\n");
  EXPECT_EQ(failure(), b + ":1: the box is empty (w or h is 0)");
  label("b.txt", "1 0.5 x 0.2 0.4\n");
  EXPECT_EQ(failure(), b + ":1: 'x' is not a number");
  label("b.txt", "1.5 0.5 0.5 0.2 0.4\n");
  EXPECT_EQ(failure().rfind(b + ":1: class 1.5 is not in the class mapping", 0), 0u);
}

TEST_F(YoloImport, ALabelWithoutItsImageIsAnError) {
  label("b.txt", "1 0.5 0.5 0.2 0.4\n");
  label("zz.txt", "1 0.5 0.5 0.2 0.4\n");
  EXPECT_EQ(failure().rfind((dir_ / "zz.txt").string() + ": no image zz.{jpg,jpeg,png,bmp}", 0), 0u)
      << failure();
}

TEST(YoloClasses, ParsesRolesAndRefusesBadItems) {
  const auto classes = parse_yolo_classes("1=person,0=crowd,3=drop");
  ASSERT_EQ(classes.size(), 3u);
  EXPECT_EQ(classes.at(1), YoloRole::kPerson);
  EXPECT_EQ(classes.at(0), YoloRole::kCrowd);
  EXPECT_EQ(classes.at(3), YoloRole::kDrop);
  EXPECT_THROW(parse_yolo_classes("1=people"), Error);
  EXPECT_THROW(parse_yolo_classes("a=person"), Error);
  EXPECT_THROW(parse_yolo_classes("1=person,1=crowd"), Error);
  EXPECT_THROW(parse_yolo_classes(""), Error);
  EXPECT_THROW(parse_yolo_classes("1person"), Error);
}

}  // namespace
}  // namespace wheelpose::dataset
