// End-to-end tests of `wheelpose eval` on the shared COCO sample and on broken inputs.
// Expected COCO numbers were cross-checked against a line-by-line port of pycocotools' COCOeval.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_runner.h"
#include "core/atomic_file.h"

namespace {

using nlohmann::json;
using wheelpose::testing::fresh_temp_dir;
using wheelpose::testing::run_wheelpose;
namespace fs = std::filesystem;

const std::string kSample = std::string(WHEELPOSE_SHARED_DIR) + "/data/coco-sample";
const std::string kGt = kSample + "/person_keypoints_sample.json";
const std::string kBoxes = kSample + "/person_detections_sample.json";

json read_json(const fs::path& path) {
  std::ifstream in(path);
  return json::parse(in);
}

void write(const fs::path& path, const std::string& text) { std::ofstream(path) << text; }

// Keypoint results made from the GT: every person shifted by a fixed pattern of up to +-3 px
// (times `scale`), and every third person also gets a higher-scored copy 25 px to the right
// (a false positive). Unlabelled GT people yield detections near the origin.
json perturbed_results(double scale) {
  const json gt = read_json(kGt);
  json out = json::array();
  int j = 0;
  for (const json& ann : gt["annotations"]) {
    json kp = ann["keypoints"];
    for (int k = 0; k < 17; ++k) {
      kp[3 * k] = kp[3 * k].get<double>() + scale * ((k * 7 + j * 3) % 5 - 2) * 1.5;
      kp[3 * k + 1] = kp[3 * k + 1].get<double>() + scale * ((k * 5 + j) % 7 - 3) * 1.0;
      kp[3 * k + 2] = 1;
    }
    out.push_back({{"image_id", ann["image_id"]},
                   {"category_id", 1},
                   {"keypoints", kp},
                   {"score", 0.9 - 0.05 * j}});
    if (j % 3 == 0) {
      json shifted = kp;
      for (int k = 0; k < 17; ++k) shifted[3 * k] = shifted[3 * k].get<double>() + 25.0;
      out.push_back({{"image_id", ann["image_id"]},
                     {"category_id", 1},
                     {"keypoints", shifted},
                     {"score", 0.95 - 0.05 * j}});
    }
    ++j;
  }
  return out;
}

void expect_stats(const json& stats_list, const std::vector<double>& expected) {
  ASSERT_EQ(stats_list.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_NEAR(stats_list[i].get<double>(), expected[i], 1e-12) << "stat " << i;
  }
}

TEST(EvalCliTest, SampleBoxesMatchPycocotools) {
  const fs::path out = fresh_temp_dir("eval_boxes");
  const auto r =
      run_wheelpose("eval --gt " + kGt + " --dt " + kBoxes + " --type bbox --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find(" Average Precision  (AP) @[ IoU=0.50:0.95 | area=   all | "
                          "maxDets=100 ] = 0.789\n"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find(" Average Recall     (AR) @[ IoU=0.50:0.95 | area=   all | "
                          "maxDets=  1 ] = 0.279\n"),
            std::string::npos);
  const json m = read_json(out / "metrics.json");
  expect_stats(m["results"]["bbox"]["stats_list"],
               {0.7891214003991492, 0.9823982398239822, 0.9823982398239822, 0.6504950495049505,
                0.7666195190947667, 0.872169532742748, 0.2785714285714286, 0.8285714285714286,
                0.8428571428571429, 0.65, 0.82, 0.9142857142857143});
  EXPECT_FALSE(m["results"].contains("keypoints"));
}

TEST(EvalCliTest, SampleKeypointsWithBaselineAndOverlay) {
  const fs::path out = fresh_temp_dir("eval_keypoints");
  write(out / "ours.json", perturbed_results(1.0).dump());
  write(out / "base.json", perturbed_results(3.0).dump());
  const auto r = run_wheelpose("eval --gt " + kGt + " --dt " + (out / "ours.json").string() +
                               " --baseline " + (out / "base.json").string() + " --out " +
                               (out / "report").string() + " --viz 1 --images " + kSample);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find(" Average Precision  (AP) @[ IoU=0.50:0.95 | area=   all | "
                          "maxDets= 20 ] = 0.584\n"),
            std::string::npos)
      << r.output;
  const json m = read_json(out / "report" / "metrics.json");
  expect_stats(m["results"]["keypoints"]["stats_list"],
               {0.5842527109853842, 0.6620635747785307, 0.6620635747785307, 0.774092409240924,
                0.7659068049662111, 0.9166666666666666, 1.0, 1.0, 0.82, 0.9857142857142858});
  expect_stats(m["baseline"]["keypoints"]["stats_list"],
               {0.2648275353851175, 0.5786868160500264, 0.13727801351563726, 0.17656765676567654,
                0.44759595739793756, 0.4916666666666666, 0.9166666666666666, 0.4166666666666667,
                0.24, 0.6714285714285715});
  // 12 labelled people (2 have num_keypoints 0 and are ignored); 181 labelled keypoints.
  const json& ours = m["results"]["keypoint_metrics"];
  EXPECT_EQ(ours["gt_people"], 12);
  EXPECT_EQ(ours["pairs"], 12);
  EXPECT_EQ(ours["overall"]["count"], 181);
  EXPECT_DOUBLE_EQ(ours["overall"]["pdj5"].get<double>(), 1.0);
  const json& base = m["baseline"]["keypoint_metrics"];
  EXPECT_EQ(base["missed_people"], 1);
  EXPECT_EQ(base["overall"]["missed"], 17);
  const double change = m["change_percent"]["keypoints"]["AP"].get<double>();
  EXPECT_NEAR(change, (0.5842527109853842 - 0.2648275353851175) / 0.2648275353851175 * 100, 1e-9);

  const std::string comparison = wheelpose::read_file(out / "report" / "comparison.md");
  EXPECT_NE(comparison.find("| Keypoint | PDJ@5 (+) | PJPE (-) | OKS50 (+) | OKS75 (+) |"),
            std::string::npos);
  EXPECT_NE(comparison.find("| KP AP | 0.265 | 0.584 | +120.62% |"), std::string::npos)
      << comparison;

  const fs::path overlay = out / "report" / "viz" / "000000000785.jpg";
  ASSERT_TRUE(fs::exists(overlay));
  const std::string jpeg = wheelpose::read_file(overlay);
  ASSERT_GT(jpeg.size(), 1000u);
  EXPECT_EQ(static_cast<unsigned char>(jpeg[0]), 0xFF);
  EXPECT_EQ(static_cast<unsigned char>(jpeg[1]), 0xD8);
}

// --bootstrap: intervals that hold the whole set's value, a paired difference, the same numbers
// for the same seed, and nothing but a usage error for a negative count.
TEST(EvalCliTest, BootstrapIntervalsOfAPAndOfAPairedDifference) {
  const fs::path out = fresh_temp_dir("eval_bootstrap");
  write(out / "ours.json", perturbed_results(1.0).dump());
  write(out / "base.json", perturbed_results(3.0).dump());
  const std::string command = "eval --gt " + kGt + " --dt " + (out / "ours.json").string() +
                              " --baseline " + (out / "base.json").string() +
                              " --bootstrap 200 --bootstrap-seed 3 --out ";
  const auto r = run_wheelpose(command + (out / "a").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("Keypoint AP, 95% interval of 200 resamples of the images (seed 3)"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("| AP | 58.4 ["), std::string::npos) << r.output;
  const json m = read_json(out / "a" / "metrics.json");
  ASSERT_EQ(m["bootstrap"].size(), 1u);
  const json& b = m["bootstrap"][0];
  EXPECT_EQ(b["type"], "keypoints");
  EXPECT_EQ(b["samples"], 200);
  for (const char* part : {"ours", "baseline", "difference"}) {
    const json& ap = b[part]["AP"];
    EXPECT_LE(ap["low"].get<double>(), ap["estimate"].get<double>()) << part;
    EXPECT_GE(ap["high"].get<double>(), ap["estimate"].get<double>()) << part;
    EXPECT_LT(ap["low"].get<double>(), ap["high"].get<double>()) << part;
  }
  EXPECT_NEAR(b["ours"]["AP"]["estimate"].get<double>(), 0.5842527109853842, 1e-12);
  EXPECT_NEAR(b["difference"]["AP"]["estimate"].get<double>(),
              0.5842527109853842 - 0.2648275353851175, 1e-12);
  // The ±1 px model beats the ±3 px one on every resample of these 4 images.
  EXPECT_GT(b["difference"]["AP"]["low"].get<double>(), 0);
  const auto again = run_wheelpose(command + (out / "b").string());
  ASSERT_EQ(again.exit_code, 0) << again.output;
  EXPECT_EQ(read_json(out / "b" / "metrics.json")["bootstrap"], m["bootstrap"]);

  const auto bad = run_wheelpose("eval --gt " + kGt + " --dt " + kBoxes +
                                 " --type bbox --bootstrap -5 --out " + (out / "c").string());
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_NE(bad.output.find("--bootstrap"), std::string::npos) << bad.output;
  EXPECT_FALSE(fs::exists(out / "c"));
}

// Each broken input must exit 2 with one line naming the file, the entry and the field.
struct BadCase {
  const char* name;
  std::string gt;       // empty: the sample GT
  std::string results;  // written to dt.json
  std::vector<std::string> expected;
};

TEST(EvalCliTest, BadInputsExitTwoWithClearMessage) {
  const fs::path dir = fresh_temp_dir("eval_bad");
  json good = perturbed_results(1.0);
  json unknown_image = good, short_keypoints = good, missing_score = good, infinite = good;
  unknown_image[3]["image_id"] = 4242;
  short_keypoints[2]["keypoints"].erase(short_keypoints[2]["keypoints"].end() - 1);
  missing_score[5].erase("score");
  std::string inf_text = infinite.dump();
  infinite[4]["score"] = 12345.5;
  inf_text = infinite.dump();
  inf_text.replace(inf_text.find("12345.5"), 7, "1e999");
  std::string nan_text = good.dump();
  nan_text.insert(1, "{\"image_id\": 785, \"category_id\": 1, \"score\": NaN, \"keypoints\": []},");
  json gt = read_json(kGt);
  gt.erase("categories");
  const std::vector<BadCase> cases = {
      {"unknown image",
       "",
       unknown_image.dump(),
       {"dt.json: results[3].image_id: image id 4242 is not in the ground truth"}},
      {"short keypoints",
       "",
       short_keypoints.dump(),
       {"dt.json: results[2].keypoints: expected 51 numbers"}},
      {"missing score", "", missing_score.dump(), {"dt.json: results[5]: missing field 'score'"}},
      {"infinite score",
       "",
       inf_text,
       {"dt.json: invalid JSON", "number overflow parsing '1e999'"}},
      {"NaN", "", nan_text, {"dt.json: malformed JSON at line 1"}},
      {"malformed", "", "[{\"image_id\": 785,", {"dt.json: malformed JSON"}},
      {"no categories", gt.dump(), good.dump(), {"gt.json: top level: missing field 'categories'"}},
      {"results not a list", "", "{}", {"dt.json: top level: expected a list"}},
  };
  for (const BadCase& c : cases) {
    std::string gt_path = kGt;
    if (!c.gt.empty()) {
      gt_path = (dir / "gt.json").string();
      write(gt_path, c.gt);
    }
    write(dir / "dt.json", c.results);
    const auto r = run_wheelpose("eval --gt " + gt_path + " --dt " + (dir / "dt.json").string() +
                                 " --out " + (dir / "out").string());
    EXPECT_EQ(r.exit_code, 2) << c.name << ": " << r.output;
    for (const auto& text : c.expected) {
      EXPECT_NE(r.output.find(text), std::string::npos) << c.name << ": " << r.output;
    }
    EXPECT_FALSE(fs::exists(dir / "out" / "metrics.json")) << c.name;
  }
}

TEST(EvalCliTest, VizNeedsImagesAndBboxResultsCannotGiveKeypoints) {
  const fs::path out = fresh_temp_dir("eval_usage");
  auto r = run_wheelpose("eval --gt " + kGt + " --dt " + kBoxes + " --viz 2");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--viz needs --images"), std::string::npos) << r.output;
  r = run_wheelpose("eval --gt " + kGt + " --dt " + kBoxes + " --type keypoints");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("results[0]: missing field 'keypoints'"), std::string::npos) << r.output;
  r = run_wheelpose("eval --gt " + kGt + " --dt " + kBoxes + " --type nonsense");
  EXPECT_EQ(r.exit_code, 2) << r.output;
}

}  // namespace
