#include "eval/realism.h"

#include <gtest/gtest.h>

#include "core/error.h"

namespace wheelpose::eval {
namespace {

using nlohmann::json;

// A standing person's 17 keypoints inside a 100 × 200 box at (x, y), all labelled visible.
json pose(double x, double y) {
  json kp = json::array();
  for (int k = 0; k < 17; ++k) kp.insert(kp.end(), {x + 5 * k, y + 11 * k, 2});
  return kp;
}

json person(int id, int image_id, double x, double y, double height, json attributes) {
  json a = {{"id", id},
            {"image_id", image_id},
            {"category_id", 1},
            {"iscrowd", 0},
            {"area", 100 * height},
            {"bbox", {x, y, 100, height}},
            {"num_keypoints", 17},
            {"keypoints", pose(x, y)}};
  for (const auto& [key, value] : attributes.items()) a[key] = value;
  return a;
}

// Three judged people: found exactly (OKS 1), missed (the detection 150 px off), nobody detected;
// and one too small and one crowd region, left out.
json ground_truth() {
  return {
      {"images",
       {{{"id", 1},
         {"file_name", "a.jpg"},
         {"width", 640},
         {"height", 480},
         {"environment", "room"}},
        {{"id", 2},
         {"file_name", "b.jpg"},
         {"width", 640},
         {"height", 480},
         {"environment", "wall"}}}},
      {"annotations",
       {person(1, 1, 10, 10, 200,
               {{"wheelchair_type", "manual"},
                {"assets", {"hair/bob", "shoes"}},
                {"body", {{"age", 20}}}}),
        person(2, 1, 300, 10, 200,
               {{"wheelchair_type", "power"}, {"assets", {"shoes"}}, {"body", {{"age", 60}}}}),
        person(3, 2, 10, 10, 200,
               {{"wheelchair_type", "manual"}, {"assets", json::array()}, {"body", {{"age", 80}}}}),
        person(4, 2, 300, 10, 60, {{"wheelchair_type", "manual"}}),
        [] {
          json crowd = person(5, 2, 400, 10, 200, json::object());
          crowd["iscrowd"] = 1;
          return crowd;
        }()}},
      {"categories", {{{"id", 1}, {"name", "person"}}}}};
}

json detection(int image_id, double x, double y) {
  json kp = pose(x, y);
  for (std::size_t k = 2; k < kp.size(); k += 3) kp[k] = 0.9;
  return {{"image_id", image_id},
          {"category_id", 1},
          {"keypoints", kp},
          {"score", 0.9},
          {"bbox", {x, y, 100, 200}}};
}

RealismReport measure(const json& root, const json& results, const RealismOptions& options = {}) {
  const coco::CocoGroundTruth gt = coco::parse_coco_gt(root, "gt.json", 17, true);
  const coco::CocoResults dt = coco::parse_coco_results(results, "dt.json", gt, 17);
  return measure_realism(root, gt, dt, load_keypoint_template("coco17"), options);
}
RealismReport measure(const json& results) { return measure(ground_truth(), results); }

const RealismGroup& group(const RealismReport& report, const std::string& key,
                          const std::string& value) {
  for (const RealismGroup& g : report.groups) {
    if (g.key == key && g.bucket == value) return g;
  }
  throw std::runtime_error("no group " + key + "=" + value);
}

TEST(Realism, TheBestMatchDecidesFoundAndItsOks) {
  // Person 1 exactly; person 2's nearest detection is 150 px off (OKS ≈ 0); image 2 has none.
  const RealismReport report =
      measure(json::array({detection(1, 10, 10), detection(1, 450, 10), detection(1, 500, 300)}));
  EXPECT_EQ(report.overall.people, 3);
  EXPECT_EQ(report.overall.found, 1);
  EXPECT_EQ(report.too_small, 1);
  EXPECT_EQ(report.crowd, 1);
  EXPECT_NEAR(report.overall.oks_sum, 1.0, 1e-3);  // 1 + ~0 + 0
  EXPECT_NEAR(report.overall.mean_oks(), 1.0 / 3, 1e-3);

  // Strings, booleans and names in lists are buckets; image attributes count for its people.
  EXPECT_EQ(group(report, "wheelchair_type", "manual").people, 2);
  EXPECT_EQ(group(report, "wheelchair_type", "manual").found, 1);
  EXPECT_EQ(group(report, "wheelchair_type", "power").found, 0);
  EXPECT_EQ(group(report, "assets", "shoes").people, 2);
  EXPECT_EQ(group(report, "assets", "hair/bob").found, 1);
  EXPECT_EQ(group(report, "environment", "room").people, 2);
  EXPECT_EQ(group(report, "environment", "wall").people, 1);
  // Nested numbers split at quantiles: ages 20, 60, 80 into [20, 60), [60, 80), [80, 80].
  EXPECT_EQ(group(report, "body.age", "[20, 60)").found, 1);
  EXPECT_EQ(group(report, "body.age", "[80, 80]").people, 1);
  // Identifiers and geometry are not attributes; one-valued numbers say nothing.
  for (const RealismGroup& g : report.groups) {
    EXPECT_NE(g.key, "id");
    EXPECT_NE(g.key, "bbox");
    EXPECT_NE(g.key, "file_name");
    EXPECT_NE(g.key, "height_px");          // every judged person is 200 px tall
    EXPECT_NE(g.key, "visible_keypoints");  // and shows all 17 keypoints
  }
}

TEST(Realism, SplitsByHowManyKeypointsShow) {
  json root = ground_truth();
  // Person 2 has 5 keypoints labelled but hidden (v = 1): 12 of 17 show.
  json& hidden = root["annotations"][1]["keypoints"];
  for (int k = 0; k < 5; ++k) hidden[3 * k + 2] = 1;
  const RealismReport report = measure(root, json::array({detection(1, 10, 10)}));
  EXPECT_EQ(report.overall.people, 3);  // hidden keypoints still count as labelled
  EXPECT_EQ(group(report, "visible_keypoints", "[12, 17)").people, 1);
  EXPECT_EQ(group(report, "visible_keypoints", "[17, 17]").people, 2);
  EXPECT_EQ(group(report, "visible_keypoints", "[17, 17]").found, 1);
}

TEST(Realism, MinVisibleJudgesAtEqualVisibility) {
  json root = ground_truth();
  // Person 2 shows 12 of 17 keypoints (5 labelled hidden, v = 1).
  json& hidden = root["annotations"][1]["keypoints"];
  for (int k = 10; k < 15; ++k) hidden[3 * k + 2] = 1;
  const json found_one = json::array({detection(1, 10, 10)});
  RealismOptions options;
  options.min_visible_keypoints = 12;
  EXPECT_EQ(measure(root, found_one, options).overall.people, 3);
  options.min_visible_keypoints = 13;
  const RealismReport report = measure(root, found_one, options);
  const coco::CocoGroundTruth gt = coco::parse_coco_gt(root, "gt.json", 17, true);
  EXPECT_EQ(report.overall.people, 2);
  EXPECT_EQ(report.too_few_visible, 1);
  EXPECT_EQ(report.overall.found, 1);
  EXPECT_TRUE(realism_judges(gt.annotations[0], options, image_sizes(root)));
  EXPECT_FALSE(realism_judges(gt.annotations[1], options, image_sizes(root)));
  EXPECT_NE(realism_markdown(report, "t").find("1 with too few visible"), std::string::npos);
  EXPECT_EQ(realism_json(report, options)["left_out"]["too_few_visible"], 1);
}

TEST(Realism, SplitsByWhetherTheFaceShows) {
  json root = ground_truth();
  // Person 1 seen from behind: nose and eyes labelled but hidden; person 3 shows one eye only.
  json& back = root["annotations"][0]["keypoints"];
  for (int k = 0; k < 3; ++k) back[3 * k + 2] = 1;
  json& one_eye = root["annotations"][2]["keypoints"];
  one_eye[2] = 1;
  one_eye[5] = 0;
  const RealismReport report = measure(root, json::array({detection(1, 10, 10)}));
  EXPECT_EQ(group(report, "face_visible", "false").people, 1);
  EXPECT_EQ(group(report, "face_visible", "false").found, 1);  // person 1 is found exactly
  EXPECT_EQ(group(report, "face_visible", "true").people, 2);
  EXPECT_EQ(group(report, "face_visible", "true").found, 0);
}

TEST(Realism, ReportsNameEveryGroup) {
  const RealismReport report = measure(json::array({detection(1, 10, 10)}));
  const std::string md = realism_markdown(report, "test");
  EXPECT_NE(md.find("| all | 3 | 33.3 % | 0.333 |"), std::string::npos) << md;
  EXPECT_NE(md.find("## wheelchair_type"), std::string::npos) << md;
  const json j = realism_json(report, RealismOptions{});
  EXPECT_EQ(j["overall"]["found"], 1);
  EXPECT_EQ(j["left_out"]["too_small"], 1);
  EXPECT_EQ(j["groups"].size(), report.groups.size());
}

TEST(Realism, JudgesBoxesWhereNoKeypointIsLabelled) {
  json root = ground_truth();
  for (json& a : root["annotations"]) {  // people labelled by box only, as the dev photos are
    for (std::size_t k = 0; k < a["keypoints"].size(); ++k) a["keypoints"][k] = 0;
    a["num_keypoints"] = 0;
  }
  // Person 1's box exactly (IoU 1); person 2's shifted by 40 of its 100 px (IoU 60/140 < 0.5);
  // nothing in image 2.
  const json results = json::array({detection(1, 10, 10), detection(1, 340, 10)});
  RealismOptions options;
  options.boxes = true;
  const RealismReport report = measure(root, results, options);
  EXPECT_EQ(report.overall.people, 3);  // no keypoints asked for
  EXPECT_EQ(report.overall.found, 1);
  EXPECT_NEAR(report.overall.oks_sum, 1.0 + 60.0 / 140.0, 1e-9);
  for (const RealismGroup& g : report.groups) EXPECT_NE(g.key, "face_visible");
  EXPECT_NE(realism_markdown(report, "t").find("| people | judged | found | mean box IoU |"),
            std::string::npos);
  EXPECT_EQ(realism_markdown(report, "t").find("too few labelled keypoints"), std::string::npos);
  const json j = realism_json(report, options);
  EXPECT_NEAR(j["overall"]["mean_iou"].get<double>(), (1.0 + 60.0 / 140.0) / 3, 1e-9);
  EXPECT_TRUE(j["options"]["boxes"].get<bool>());
  // Judged by keypoints the same set has nobody to judge.
  EXPECT_EQ(measure(root, results).overall.people, 0);
}

TEST(Realism, InFrameLeavesOutPeopleTheFrameCuts) {
  json root = ground_truth();
  root["annotations"][1]["bbox"] = {540, 10, 100, 200};  // its right edge on the 640 px border
  RealismOptions options;
  options.whole_in_frame = true;
  const RealismReport report = measure(root, json::array({detection(1, 10, 10)}), options);
  EXPECT_EQ(report.overall.people, 2);
  EXPECT_EQ(report.cut_by_frame, 1);
  EXPECT_NE(realism_markdown(report, "t").find("1 cut by the frame"), std::string::npos);
  EXPECT_EQ(realism_json(report, options)["left_out"]["cut_by_frame"], 1);
  // Without the images' sizes the border is unknown: an error naming the image.
  root["images"][0].erase("width");
  try {
    measure(root, json::array(), options);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("image 1: no width and height"), std::string::npos)
        << e.what();
  }
}

TEST(Realism, ResultsWithoutKeypointsAreRefused) {
  const json root = ground_truth();
  const coco::CocoGroundTruth gt = coco::parse_coco_gt(root, "gt.json", 17, true);
  const coco::CocoResults boxes = coco::parse_coco_results(
      json::array({{{"image_id", 1}, {"category_id", 1}, {"bbox", {1, 1, 5, 5}}, {"score", 1}}}),
      "boxes.json", gt, 17);
  EXPECT_THROW(measure_realism(root, gt, boxes, load_keypoint_template("coco17"), {}), Error);
}

}  // namespace
}  // namespace wheelpose::eval
