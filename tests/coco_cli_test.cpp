// End-to-end tests of `wheelpose coco validate|merge|sample|split|export|viz` on the shared COCO
// sample and on small hand-made files, including broken ones.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <set>
#include <string>
#include <vector>

#include "cli_runner.h"

namespace {

using nlohmann::json;
using wheelpose::testing::fresh_temp_dir;
using wheelpose::testing::read_text;
using wheelpose::testing::run_wheelpose;
namespace fs = std::filesystem;

const std::string kSampleDir = std::string(WHEELPOSE_SHARED_DIR) + "/data/coco-sample";
const std::string kSample = kSampleDir + "/person_keypoints_sample.json";

json read_json(const fs::path& path) { return json::parse(read_text(path)); }
void write(const fs::path& path, const std::string& text) { std::ofstream(path) << text; }

json coco17_category() { return read_json(kSample)["categories"]; }

// A person in a 200x100 image: box [20, 10, 40, 50], nose visible at (30, 20), left eye
// occluded at (35, 18), the rest unlabelled.
json tiny_coco() {
  json kp = json::array();
  for (int k = 0; k < 17; ++k) {
    if (k == 0)
      kp.insert(kp.end(), {30, 20, 2});
    else if (k == 1)
      kp.insert(kp.end(), {35, 18, 1});
    else
      kp.insert(kp.end(), {0, 0, 0});
  }
  return {{"images", {{{"id", 1}, {"file_name", "a.png"}, {"width", 200}, {"height", 100}}}},
          {"annotations",
           {{{"id", 1},
             {"image_id", 1},
             {"category_id", 1},
             {"bbox", {20, 10, 40, 50}},
             {"area", 1500},
             {"iscrowd", 0},
             {"num_keypoints", 2},
             {"keypoints", kp}}}},
          {"categories", coco17_category()}};
}

// `n` images of 100x100 in clips of `per_clip` frames (motion_id "clip<k>" on the image).
json clip_coco(int n, int per_clip) {
  json images = json::array(), anns = json::array();
  json kp = json::array();
  for (int k = 0; k < 17; ++k) kp.insert(kp.end(), {50, 50, 2});
  for (int i = 1; i <= n; ++i) {
    images.push_back({{"id", i},
                      {"file_name", "f" + std::to_string(i) + ".png"},
                      {"width", 100},
                      {"height", 100},
                      {"motion_id", "clip" + std::to_string((i - 1) / per_clip)}});
    anns.push_back({{"id", i},
                    {"image_id", i},
                    {"category_id", 1},
                    {"bbox", {10, 10, 50, 80}},
                    {"area", 4000},
                    {"iscrowd", 0},
                    {"num_keypoints", 17},
                    {"keypoints", kp}});
  }
  return {{"images", images}, {"annotations", anns}, {"categories", coco17_category()}};
}

TEST(CocoValidate, SharedSampleIsValid) {
  const auto r = run_wheelpose("coco validate " + kSample);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find(kSample + ": valid (4 images, 14 annotations, 1 categories)"),
            std::string::npos)
      << r.output;
}

TEST(CocoValidate, ReportsEveryProblemWithItsPath) {
  const fs::path dir = fresh_temp_dir("coco_validate_problems");
  json c = tiny_coco();
  json bad = c["annotations"][0];
  bad["id"] = 1;                     // duplicate
  bad["image_id"] = 7;               // no such image
  bad["keypoints"][3 * 5] = 250;     // left_shoulder x outside (but v=0 -> nonzero)
  bad["keypoints"][3 * 16 + 2] = 3;  // bad visibility
  c["annotations"].push_back(bad);
  json worse = c["annotations"][0];
  worse["id"] = 3;
  worse["keypoints"][0] = 500;  // visible nose outside the 200x100 image
  worse["num_keypoints"] = 5;
  worse["area"] = 0;
  worse["bbox"] = {180, 10, 40, 50};  // extends past x = 200
  c["annotations"].push_back(worse);
  json short_kp = c["annotations"][0];
  short_kp["id"] = 4;
  short_kp["keypoints"].erase(short_kp["keypoints"].begin());
  c["annotations"].push_back(short_kp);
  c["images"].push_back({{"id", 5}, {"file_name", "c.png"}, {"height", 10}});
  c["images"].push_back({{"id", 0}, {"file_name", "b.png"}, {"width", 10}, {"height", 10}});
  const fs::path file = dir / "bad.json";
  write(file, c.dump());
  const auto r = run_wheelpose("coco validate " + file.string());
  EXPECT_EQ(r.exit_code, 2);
  const std::string f = file.string() + ": ";
  for (const std::string& line : std::vector<std::string>{
           f + "images[1].width: missing",
           f + "images[2].id: must be >= 1, got 0",
           f + "annotations[1].id: duplicate id 1 (first at annotations[0])",
           f + "annotations[1].image_id: no image has id 7",
           f + "annotations[1].keypoints[5] (left_shoulder): unlabelled (v=0) but at (250, 0), "
               "not (0, 0)",
           f + "annotations[1].keypoints[16] (right_ankle): visibility must be 0, 1 or 2, got 3",
           f + "annotations[2].area: must be positive, got 0",
           f + "annotations[2].bbox: box [180, 10, 40, 50] extends outside the 200x100 image",
           f + "annotations[2].keypoints[0] (nose): v=2 but (500, 20) lies outside the 200x100 "
               "image",
           f + "annotations[2].num_keypoints: is 5 but 2 keypoints have v > 0",
           f + "annotations[3].keypoints: expected 51 numbers (17 keypoints x 3), got 50",
           "error: " + f + "11 problem(s) in 3 images, 4 annotations, 1 categories",
       }) {
    EXPECT_NE(r.output.find(line + "\n"), std::string::npos) << "missing: " << line << "\n"
                                                             << r.output;
  }
}

TEST(CocoValidate, InvalidJsonIsOneLineWithPosition) {
  const fs::path dir = fresh_temp_dir("coco_validate_json");
  write(dir / "broken.json", "{\"images\": [\n  {\"id\": 1,,}\n]}");
  const auto r = run_wheelpose("coco validate " + (dir / "broken.json").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("error: " + (dir / "broken.json").string() +
                          ": malformed JSON at line 2 (byte 25"),
            std::string::npos)
      << r.output;
}

TEST(CocoValidate, MissingTopLevelKeys) {
  const fs::path dir = fresh_temp_dir("coco_validate_keys");
  write(dir / "empty.json", "{\"images\": {}}");
  const auto r = run_wheelpose("coco validate " + (dir / "empty.json").string());
  EXPECT_EQ(r.exit_code, 2);
  const std::string f = (dir / "empty.json").string() + ": ";
  EXPECT_NE(r.output.find(f + "categories: missing\n"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(f + "images: expected an array\n"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(f + "annotations: missing\n"), std::string::npos) << r.output;
}

TEST(CocoValidate, ImagesDirectoryChecksFiles) {
  const auto r = run_wheelpose("coco validate " + kSample + " --images " + kSampleDir);
  EXPECT_EQ(r.exit_code, 2);
  // Only 000000000785.jpg is shipped with the sample.
  EXPECT_EQ(r.output.find("images[0].file_name"), std::string::npos) << r.output;
  EXPECT_NE(
      r.output.find(kSample + ": images[1].file_name: no file " + kSampleDir + "/000000040083.jpg"),
      std::string::npos)
      << r.output;
}

// The halves of the sample, each with its own ids, merge into the bytes of the whole.
TEST(CocoMerge, HalvesMergeToTheWhole) {
  const fs::path dir = fresh_temp_dir("coco_merge_halves");
  const json all = read_json(kSample);
  json a = all, b = all;
  a["images"] = json::array();
  b["images"] = json::array();
  a["annotations"] = json::array();
  b["annotations"] = json::array();
  std::set<long> first_half = {785, 40083};
  for (const json& im : all["images"]) (first_half.count(im["id"]) ? a : b)["images"].push_back(im);
  for (const json& an : all["annotations"]) {
    (first_half.count(an["image_id"]) ? a : b)["annotations"].push_back(an);
  }
  write(dir / "a.json", a.dump());
  write(dir / "b.json", b.dump(2));
  auto r = run_wheelpose("coco merge " + kSample + " --out " + (dir / "whole.json").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run_wheelpose("coco merge " + (dir / "a.json").string() + " " + (dir / "b.json").string() +
                    " --out " + (dir / "merged.json").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string whole = read_text(dir / "whole.json");
  EXPECT_EQ(read_text(dir / "merged.json"), whole);
  const json m = json::parse(whole);
  ASSERT_EQ(m["images"].size(), 4u);
  EXPECT_EQ(m["images"][0]["id"], 1);
  EXPECT_EQ(m["images"][0]["file_name"], "000000000785.jpg");
  EXPECT_EQ(m["images"][3]["id"], 4);
  EXPECT_EQ(m["images"][3]["file_name"], "000000197388.jpg");
  ASSERT_EQ(m["annotations"].size(), 14u);
  // Annotations follow image order, then old id: 785's, then 40083's (198196, 230195, 1202706).
  EXPECT_EQ(m["annotations"][0]["area"], 27789.11055);
  EXPECT_EQ(m["annotations"][1]["id"], 2);
  EXPECT_EQ(m["annotations"][1]["image_id"], 2);
  EXPECT_EQ(m["annotations"][1]["area"], 11025.219);
  EXPECT_EQ(m["annotations"][13]["id"], 14);
  // Canonical form: one element per line, sorted top-level keys, final newline.
  EXPECT_EQ(whole.substr(0, 18), "{\n\"annotations\": [");
  EXPECT_EQ(whole.back(), '\n');
  // Canonical output is a fixed point.
  r = run_wheelpose("coco merge " + (dir / "whole.json").string() + " --out " +
                    (dir / "again.json").string());
  EXPECT_EQ(read_text(dir / "again.json"), whole);
}

TEST(CocoMerge, CategoriesMustAgreeAndNamesMustBeUnique) {
  const fs::path dir = fresh_temp_dir("coco_merge_errors");
  json other = read_json(kSample);
  other["categories"][0]["keypoints"][0] = "head";
  write(dir / "other.json", other.dump());
  auto r = run_wheelpose("coco merge " + kSample + " " + (dir / "other.json").string() + " --out " +
                         (dir / "m.json").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("error: " + (dir / "other.json").string() + ": categories differ from " +
                          kSample),
            std::string::npos)
      << r.output;
  r = run_wheelpose("coco merge " + kSample + " " + kSample + " --out " +
                    (dir / "m.json").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("images[0].file_name: '000000000785.jpg' is also an image of"),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(dir / "m.json"));
}

TEST(CocoMerge, ReplaceByFilenameRelabels) {
  const fs::path dir = fresh_temp_dir("coco_merge_replace");
  json relabel = tiny_coco();
  relabel["images"][0] = {
      {"id", 9}, {"file_name", "000000040083.jpg"}, {"width", 500}, {"height", 333}};
  relabel["annotations"][0]["image_id"] = 9;
  relabel["annotations"][0]["id"] = 77;
  write(dir / "relabel.json", relabel.dump());
  const auto r = run_wheelpose("coco merge " + kSample + " " + (dir / "relabel.json").string() +
                               " --replace-by-filename --out " + (dir / "m.json").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json m = read_json(dir / "m.json");
  EXPECT_EQ(m["images"].size(), 4u);
  // 40083 (new id 2) had 3 people; now the one relabelled person. 14 - 3 + 1 = 12.
  ASSERT_EQ(m["annotations"].size(), 12u);
  EXPECT_EQ(m["annotations"][1]["image_id"], 2);
  EXPECT_EQ(m["annotations"][1]["bbox"], json({20, 10, 40, 50}));
  EXPECT_EQ(m["annotations"][1]["category_id"], 1);
  EXPECT_EQ(m["annotations"][2]["image_id"], 3);
  for (std::size_t i = 0; i < 12; ++i) EXPECT_EQ(m["annotations"][i]["id"], i + 1);
  // An image unknown to the base is an error naming it.
  relabel["images"][0]["file_name"] = "nope.jpg";
  write(dir / "relabel2.json", relabel.dump());
  const auto bad = run_wheelpose("coco merge " + kSample + " " + (dir / "relabel2.json").string() +
                                 " --replace-by-filename --out " + (dir / "m2.json").string());
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.output.find("error: " + (dir / "relabel2.json").string() +
                            ": images[0].file_name: 'nope.jpg' is not an image of the base"),
            std::string::npos)
      << bad.output;
}

TEST(CocoSample, EvenIncludesBothEnds) {
  const fs::path dir = fresh_temp_dir("coco_sample_even");
  write(dir / "clips.json", clip_coco(10, 5).dump());
  const auto r = run_wheelpose("coco sample " + (dir / "clips.json").string() +
                               " --n 4 --even --out " + (dir / "s.json").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json s = read_json(dir / "s.json");
  // round(i * 9 / 3) = 0, 3, 6, 9 -> ids 1, 4, 7, 10.
  ASSERT_EQ(s["images"].size(), 4u);
  EXPECT_EQ(s["images"][0]["id"], 1);
  EXPECT_EQ(s["images"][1]["id"], 4);
  EXPECT_EQ(s["images"][2]["id"], 7);
  EXPECT_EQ(s["images"][3]["id"], 10);
  EXPECT_EQ(s["annotations"].size(), 4u);
}

TEST(CocoSample, SeededIsDeterministic) {
  const fs::path dir = fresh_temp_dir("coco_sample_seed");
  const fs::path in = dir / "clips.json";
  write(in, clip_coco(60, 5).dump());
  for (const char* name : {"a", "b"}) {
    ASSERT_EQ(run_wheelpose("coco sample " + in.string() + " --n 20 --seed 7 --out " +
                            (dir / name).string() + ".json")
                  .exit_code,
              0);
  }
  ASSERT_EQ(run_wheelpose("coco sample " + in.string() + " --n 20 --seed 8 --out " +
                          (dir / "c.json").string())
                .exit_code,
            0);
  EXPECT_EQ(read_text(dir / "a.json"), read_text(dir / "b.json"));
  EXPECT_NE(read_text(dir / "a.json"), read_text(dir / "c.json"));
  const json a = read_json(dir / "a.json");
  EXPECT_EQ(a["images"].size(), 20u);
  EXPECT_EQ(a["annotations"].size(), 20u);
  const auto r =
      run_wheelpose("coco sample " + in.string() + " --n 61 --out " + (dir / "d.json").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("cannot sample 61 of 60 images (--n must be in 1..60)"),
            std::string::npos)
      << r.output;
}

TEST(CocoSplit, MotionClipsNeverStraddle) {
  const fs::path dir = fresh_temp_dir("coco_split");
  const fs::path in = dir / "clips.json";
  write(in, clip_coco(100, 5).dump());
  auto r = run_wheelpose("coco split " + in.string() + " --ratios 0.8,0.1,0.1 --seed 3 --out " +
                         (dir / "out").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::map<std::string, std::string> clip_part;
  std::set<int> seen;
  std::map<std::string, int> sizes;
  for (const char* part : {"train", "val", "test"}) {
    const json j = read_json(dir / "out" / (std::string(part) + ".json"));
    sizes[part] = static_cast<int>(j["images"].size());
    for (const json& im : j["images"]) {
      EXPECT_TRUE(seen.insert(im["id"].get<int>()).second);
      const std::string clip = im["motion_id"];
      const auto [it, inserted] = clip_part.emplace(clip, part);
      EXPECT_EQ(it->second, part) << clip << " straddles splits";
    }
    EXPECT_EQ(j["annotations"].size(), j["images"].size());
  }
  EXPECT_EQ(seen.size(), 100u);
  // 20 clips of 5: whole clips reach the targets 80/10/10 exactly.
  EXPECT_EQ(sizes["train"], 80);
  EXPECT_EQ(sizes["val"], 10);
  EXPECT_EQ(sizes["test"], 10);
  ASSERT_EQ(
      run_wheelpose("coco split " + in.string() + " --seed 3 --out " + (dir / "again").string())
          .exit_code,
      0);
  EXPECT_EQ(read_text(dir / "again" / "val.json"), read_text(dir / "out" / "val.json"));
  r = run_wheelpose("coco split " + in.string() + " --ratios 0.8,x --out " + (dir / "x").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("error: --ratios: 'x' is not a number"), std::string::npos) << r.output;
}

TEST(CocoExport, YoloPoseLabelsByHand) {
  const fs::path dir = fresh_temp_dir("coco_export");
  write(dir / "tiny.json", tiny_coco().dump());
  const auto r = run_wheelpose("coco export " + (dir / "tiny.json").string() +
                               " --format yolo-pose --out " + (dir / "yolo").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // Box [20,10,40,50] in 200x100: centre (40/200, 35/100), size (0.2, 0.5).
  std::string expected =
      "0 0.200000 0.350000 0.200000 0.500000 0.150000 0.200000 2 0.175000 0.180000 1";
  for (int k = 2; k < 17; ++k) expected += " 0.000000 0.000000 0";
  EXPECT_EQ(read_text(dir / "yolo" / "labels" / "a.txt"), expected + "\n");
  const std::string yaml = read_text(dir / "yolo" / "data.yaml");
  EXPECT_NE(yaml.find("kpt_shape: [17, 3]\n"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("flip_idx: [0, 2, 1, 4, 3, 6, 5, 8, 7, 10, 9, 12, 11, 14, 13, 16, 15]\n"),
            std::string::npos)
      << yaml;
  EXPECT_NE(yaml.find("names:\n  0: \"person\"\n"), std::string::npos) << yaml;
}

TEST(CocoExport, SharedSampleAndBrokenInput) {
  const fs::path dir = fresh_temp_dir("coco_export_sample");
  auto r = run_wheelpose("coco export " + kSample + " --out " + (dir / "yolo").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // 197388 has five people.
  const std::string labels = read_text(dir / "yolo" / "labels" / "000000197388.txt");
  EXPECT_EQ(std::count(labels.begin(), labels.end(), '\n'), 5);
  json bad = tiny_coco();
  bad["annotations"][0].erase("bbox");
  write(dir / "bad.json", bad.dump());
  r = run_wheelpose("coco export " + (dir / "bad.json").string() + " --out " +
                    (dir / "y2").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(
      r.output.find("error: " + (dir / "bad.json").string() + ": annotations[0].bbox: missing"),
      std::string::npos)
      << r.output;
}

TEST(CocoViz, DrawsOverlaysAndContactSheet) {
  const fs::path dir = fresh_temp_dir("coco_viz");
  const auto r = run_wheelpose("coco viz " + kSample + " --images " + kSampleDir + " --n 1 --out " +
                               (dir / "viz").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const cv::Mat overlay = cv::imread((dir / "viz" / "000000000785.png").string());
  const cv::Mat original = cv::imread(kSampleDir + "/000000000785.jpg");
  ASSERT_FALSE(overlay.empty());
  EXPECT_EQ(overlay.cols, 640);
  EXPECT_EQ(overlay.rows, 425);
  // The visible nose (first keypoint) has a white outline 4 px from its centre.
  const json ann = read_json(kSample)["annotations"][0];
  const int nx = static_cast<int>(std::lround(ann["keypoints"][0].get<double>()));
  const int ny = static_cast<int>(std::lround(ann["keypoints"][1].get<double>()));
  const cv::Vec3b ring = overlay.at<cv::Vec3b>(ny, nx + 4);
  EXPECT_GT(ring[0] + ring[1] + ring[2], 600) << "nose outline not white";
  EXPECT_GT(cv::norm(overlay, original, cv::NORM_L1), 0.0);
  EXPECT_FALSE(cv::imread((dir / "viz" / "contact_sheet.png").string()).empty());
  // --plain: the frame as it is, no overlay.
  const auto plain = run_wheelpose("coco viz " + kSample + " --images " + kSampleDir +
                                   " --n 1 --plain --out " + (dir / "plain").string());
  ASSERT_EQ(plain.exit_code, 0) << plain.output;
  EXPECT_EQ(
      cv::norm(cv::imread((dir / "plain" / "000000000785.png").string()), original, cv::NORM_INF),
      0.0);
  // Images that are not there are named.
  const auto missing = run_wheelpose("coco viz " + kSample + " --images " + dir.string() +
                                     " --out " + (dir / "v2").string());
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.output.find("image '000000000785.jpg': cannot read"), std::string::npos)
      << missing.output;
}

// A real-photo set's YOLO boxes scored as `eval --type bbox` scores them: the people of one class
// found, the other class's boxes neither rewarded nor punished.
TEST(CocoImportYolo, BoxesScoreWithEvalAndBadLabelsAreRefused) {
  const fs::path dir = fresh_temp_dir("coco_import_yolo");
  fs::create_directories(dir / "images");
  fs::create_directories(dir / "labels");
  cv::imwrite((dir / "images" / "p.jpg").string(), cv::Mat(100, 200, CV_8UC3, cv::Scalar(1, 2, 3)));
  write(dir / "labels" / "p.txt", "1 0.5 0.5 0.2 0.4\n0 0.1 0.2 0.1 0.2\n");
  const fs::path gt = dir / "gt.json";
  const std::string base = "coco import-yolo --images " + (dir / "images").string() + " --labels " +
                           (dir / "labels").string() + " --out " + gt.string();
  auto r = run_wheelpose(base + " --classes 1=person,0=crowd");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(run_wheelpose("coco validate " + gt.string()).exit_code, 0);
  // The person exactly (AP 1) and a detection on the crowd box (ignored, so AP stays 1).
  write(dir / "dt.json",
        R"([{"image_id": 1, "category_id": 1, "bbox": [80, 30, 40, 40], "score": 0.9},
            {"image_id": 1, "category_id": 1, "bbox": [10, 10, 20, 20], "score": 0.95}])");
  r = run_wheelpose("eval --type bbox --gt " + gt.string() + " --dt " + (dir / "dt.json").string() +
                    " --out " + (dir / "eval").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json metrics = read_json(dir / "eval" / "metrics.json");
  EXPECT_DOUBLE_EQ(metrics["results"]["bbox"]["stats"]["AP"].get<double>(), 1.0);

  fs::remove(gt);
  const std::string label = (dir / "labels" / "p.txt").string();
  const struct {
    std::string text, classes, says;
  } cases[] = {
      {"1 0.5 0.5 0.2\n", "1=person,0=crowd", label + ":1: expected 5 values"},
      {"3 0.5 0.5 0.2 0.4\n", "1=person,0=crowd",
       label + ":1: class 3 is not in the class mapping"},
      {"1 0.5 1.2 0.2 0.4\n", "1=person", label + ":1: value 3 (1.2) is outside [0, 1]"},
      {"1 0.5 0.5 0.2 0.4\n", "1=persons", "--classes: '1=persons' is not CLASS=ROLE"},
      {"1 0.5 0.5 0.2 0.4\n", "1=person,", "--classes: '1=person,' has an empty item"},
      {"1.0 0.5 0.5 0.2 0.4\n", "1=person", label + ":1: class '1.0' is not a whole number"},
      {"1 0.5 0.5 1e-320 0.4\n", "1=person",
       label + ":1: the box has no area in the 200x100 image (w 1e-320, h 0.4)"},
      {std::string("1 0.5 0.5 0.2 0.4\0\n", 19), "1=person",
       label + ":1: '0.4\\x00' is not a number"},
  };
  for (const auto& c : cases) {
    write(dir / "labels" / "p.txt", c.text);
    r = run_wheelpose(base + " --classes " + c.classes);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find(c.says), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(gt));
  }
  write(dir / "labels" / "p.txt", "1 0.5 0.5 0.2 0.4\n");
  write(dir / "labels" / "q.txt", "1 0.5 0.5 0.2 0.4\n");
  r = run_wheelpose(base + " --classes 1=person");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find((dir / "labels" / "q.txt").string() + ": no image q."), std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(gt));
  fs::remove(dir / "labels" / "q.txt");

  // One rule with predict: an empty image folder is an error.
  fs::create_directories(dir / "none");
  r = run_wheelpose("coco import-yolo --images " + (dir / "none").string() +
                    " --classes 1=person --out " + gt.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("none: no images"), std::string::npos) << r.output;
  // An --out that is a folder, or in a folder that does not exist: exit 2 naming it, before work.
  r = run_wheelpose("coco import-yolo --images " + (dir / "images").string() + " --labels " +
                    (dir / "labels").string() + " --classes 1=person --out " + dir.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find(dir.string() + ": is a directory"), std::string::npos) << r.output;
  r = run_wheelpose("coco import-yolo --images " + (dir / "images").string() + " --labels " +
                    (dir / "labels").string() + " --classes 1=person --out " +
                    (dir / "nowhere" / "gt.json").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("nowhere/gt.json: cannot create"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find(".tmp-"), std::string::npos) << r.output;
}

}  // namespace
