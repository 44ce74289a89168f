#include "dataset/yolo_import.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <random>
#include <sstream>

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
  EXPECT_EQ(failure(), b + ":1: class '1.5' is not a whole number");
  label("b.txt", "0.0 0.5 0.5 0.2 0.4\n");
  EXPECT_EQ(failure(), b + ":1: class '0.0' is not a whole number");
  // A width that is positive but vanishes at the image's size (1e-320 × 200 px).
  label("b.txt", "1 0.5 0.5 1e-320 0.4\n");
  EXPECT_EQ(failure(), b + ":1: the box has no area in the 200x100 image (w 1e-320, h 0.4)");
  // Invisible bytes are shown: a NUL inside a value, a byte-order mark inside one.
  label("b.txt", std::string("1 0.5 0.5 0.2 0.4\0x\n", 20));
  EXPECT_EQ(failure(), b + ":1: '0.4\\x00x' is not a number");
  label("b.txt",
        "1 \xEF\xBB\xBF"
        "0.5 0.5 0.2 0.4\n");
  EXPECT_EQ(failure(), b + ":1: '\\xEF\\xBB\\xBF0.5' is not a number");
}

TEST_F(YoloImport, AByteOrderMarkAtTheStartIsSkipped) {
  label("b.txt",
        "\xEF\xBB\xBF"
        "1 0.5 0.5 0.2 0.4\n");
  EXPECT_EQ(import()["annotations"].size(), 1u);
}

TEST_F(YoloImport, AnEmptyFolderOrANameThatIsNotUtf8IsAnError) {
  const fs::path empty = dir_ / "empty";
  fs::create_directories(empty);
  YoloImportOptions options;
  options.images_dir = empty;
  options.classes = parse_yolo_classes("1=person");
  try {
    import_yolo(options, load_keypoint_template("coco17"));
    ADD_FAILURE() << "an empty folder was imported";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              empty.string() + ": no images (.jpg, .jpeg, .png, .bmp) to import");
  }
  cv::imwrite((dir_ / "caf\xE9.png").string(), cv::Mat(10, 10, CV_8UC3, cv::Scalar(9, 9, 9)));
  EXPECT_EQ(failure(), dir_.string() +
                           ": image name 'caf\\xE9.png' is not UTF-8, so a COCO file (JSON text) "
                           "cannot name it; rename it");
}

TEST_F(YoloImport, ALabelWithoutItsImageIsAnError) {
  label("b.txt", "1 0.5 0.5 0.2 0.4\n");
  label("zz.txt", "1 0.5 0.5 0.2 0.4\n");
  EXPECT_EQ(failure().rfind((dir_ / "zz.txt").string() + ": no image zz.{jpg,jpeg,png,bmp}", 0), 0u)
      << failure();
}

// Fuzzing the label parser: hostile values and random byte changes in a valid label file. Every
// import either fails with one Error or writes a file `coco validate` accepts.
TEST_F(YoloImport, HostileLabelsFailCleanlyOrImportValidFiles) {
  const std::string valid = "1 0.5 0.5 0.2 0.4\n0 0.1 0.2 0.1 0.2";
  const std::vector<std::string> hostile = {"1e-320",
                                            "-0",
                                            "nan",
                                            "inf",
                                            "1e308",
                                            "0x1p-3",
                                            "0.0",
                                            "1",
                                            "+0.5",
                                            "-1",
                                            "2",
                                            "1.0000001",
                                            "9999999999",
                                            "1e-5",
                                            std::string("0.5\0", 4),
                                            "\xEF\xBB\xBF"
                                            "0.5",
                                            "\xFF",
                                            "0.5,0.5",
                                            "",
                                            "\t",
                                            "\r",
                                            "1.5e0",
                                            "0.999999999999999999999"};
  std::mt19937 random(20261206);
  int imported = 0, refused = 0;
  for (int trial = 0; trial < 400; ++trial) {
    std::istringstream in(valid);
    std::vector<std::string> words;
    for (std::string w; in >> w;) words.push_back(w);
    std::string text;
    for (std::size_t i = 0; i < words.size(); ++i) {
      const bool mutate = random() % 6 == 0;
      text += (mutate ? hostile[random() % hostile.size()] : words[i]) +
              (i == 4 ? "\n" : (i + 1 == words.size() ? "\n" : " "));
    }
    if (trial % 3 == 0 && !text.empty()) {
      text[random() % text.size()] = static_cast<char>(random() % 256);  // a random byte
    }
    label("b.txt", text);
    try {
      const json root = import("0=person,1=crowd");
      const auto problems = validate_coco(root);
      EXPECT_TRUE(problems.empty()) << "imported but invalid: " << problems[0].message << "\n"
                                    << text;
      ++imported;
    } catch (const Error& e) {
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
      ++refused;
    }
  }
  // Both outcomes are exercised.
  EXPECT_GT(imported, 20);
  EXPECT_GT(refused, 100);
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
  try {
    parse_yolo_classes("0=person,");
    ADD_FAILURE() << "a trailing comma was taken";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              "--classes: '0=person,' has an empty item (expected e.g. 1=person,0=crowd)");
  }
}

}  // namespace
}  // namespace wheelpose::dataset
