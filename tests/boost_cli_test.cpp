// The model-boosting experiment end to end at its --quick size: scripts/boost.sh generates a
// training and a held-out test set, scores the pretrained model, fine-tunes it, scores it again
// (validating and keeping the best weights) with the transfer recipe, scores both on the
// realistic test set and on people without wheelchairs (generated standing people and the real
// COCO sample, with keypoints and as boxes alone), runs the training-set size ablation and
// the run with standing people mixed into training, and writes the report as Markdown and HTML.

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_runner.h"

namespace {

namespace fs = std::filesystem;
using wheelpose::testing::fresh_temp_dir;
using wheelpose::testing::read_text;
using wheelpose::testing::write_coco_sample_gt;

std::size_t count_of(const std::string& text, const std::string& part) {
  std::size_t n = 0;
  for (auto at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++n;
  return n;
}

TEST(BoostScript, QuickRunWritesTheComparison) {
  if (!fs::exists(fs::path(WHEELPOSE_SOURCE_DIR) / "models" / "movenet-multipose.json")) {
    GTEST_SKIP() << "MoveNet models missing: run scripts/setup.sh";
  }
  const fs::path dir = fresh_temp_dir("boost_quick");
  fs::create_directories(dir / "real");
  const fs::path real = write_coco_sample_gt(dir / "real", /*copy_image=*/true);
  // A review ranking that drops the first training clip: training must never play it.
  const fs::path source = WHEELPOSE_SOURCE_DIR;
  auto clips = nlohmann::json::parse(read_text(source / "configs" / "boost-train-clips.json"));
  const std::string dropped = clips["kept"][0]["id"];
  clips["kept"].erase(0);
  const std::size_t kept = clips["kept"].size();
  const fs::path ranking = dir / "ranking.json";
  std::ofstream(ranking) << clips.dump();
  // The same people as boxes alone (as `coco import-yolo` gives real photos): scored for boxes.
  auto boxes = nlohmann::json::parse(read_text(real));
  for (auto& a : boxes["annotations"]) {
    a["keypoints"] = nlohmann::json::array();
    for (int k = 0; k < 51; ++k) a["keypoints"].push_back(0);
    a["num_keypoints"] = 0;
  }
  const fs::path real_boxes = dir / "real" / "boxes.json";
  std::ofstream(real_boxes) << boxes.dump();
  const fs::path out = dir / "run";
  const std::string command =
      "PULL=50 DISTILL=0.5 WISE=0.5 ENSEMBLE=1 bash " + (source / "scripts" / "boost.sh").string() +
      " --quick --recipe transfer --ablate --mix-standing --ranking " + ranking.string() +
      " --real " + real.string() + " --real " + real_boxes.string() + " " + out.string() + " > " +
      (dir / "log.txt").string() + " 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << read_text(dir / "log.txt");
  const std::string report = read_text(out / "report.md");
  EXPECT_NE(report.find("the " + std::to_string(kept) + " of configs/boost-train-clips.json's " +
                        std::to_string(kept + 1) + " clips that"),
            std::string::npos)
      << report;
  for (const char* set : {"train", "val", "standing-train"}) {
    const auto labels = nlohmann::json::parse(read_text(out / set / "annotations.json"));
    for (const auto& person : labels["annotations"]) EXPECT_NE(person["motion_id"], dropped) << set;
  }
  EXPECT_NE(report.find("| KP AP | "), std::string::npos) << report;
  EXPECT_NE(report.find("| BB AP | "), std::string::npos) << report;
  EXPECT_NE(report.find("No clip is shared"), std::string::npos) << report;
  EXPECT_NE(report.find("wear clothes or hair training never drew"), std::string::npos) << report;
  EXPECT_NE(report.find("| Model | KP AP | KP AP50 |"), std::string::npos) << report;
  EXPECT_TRUE(fs::exists(out / "run" / "last.pt"));
  EXPECT_TRUE(fs::exists(out / "run" / "best.pt"));
  const std::string train_log = read_text(out / "run" / "train_log.csv");
  EXPECT_TRUE(fs::exists(out / "run" / "curves.png"));
  const std::string html = read_text(out / "report.html");
  EXPECT_NE(html.find("<img src=\"run/curves.png\">"), std::string::npos) << html;
  EXPECT_NE(html.find("<td> KP AP </td>"), std::string::npos) << html;
  EXPECT_TRUE(fs::exists(out / "finetuned.json"));
  // People without wheelchairs, generated and real, before and after.
  EXPECT_NE(report.find("## People without wheelchairs"), std::string::npos) << report;
  EXPECT_NE(report.find("Real people (real-gt): 1 images"), std::string::npos) << report;
  EXPECT_NE(report.find("Real people (real-boxes): 1 images"), std::string::npos) << report;
  for (const char* scored :
       {"standing-baseline.json", "standing-finetuned.json", "real-gt-baseline.json",
        "real-gt-finetuned.json", "real-boxes-baseline.json", "real-boxes-finetuned.json",
        "test-realistic-baseline.json", "test-realistic-finetuned.json"})
    EXPECT_TRUE(fs::exists(out / scored)) << scored;
  // Keypoints where the file has them, boxes alone where it has none.
  const auto gt_metrics = nlohmann::json::parse(read_text(out / "real-gt-eval" / "metrics.json"));
  const auto box_metrics =
      nlohmann::json::parse(read_text(out / "real-boxes-eval" / "metrics.json"));
  EXPECT_TRUE(gt_metrics["results"].contains("keypoints"));
  EXPECT_FALSE(box_metrics["results"].contains("keypoints"));
  EXPECT_EQ(gt_metrics["results"]["bbox"]["stats"], box_metrics["results"]["bbox"]["stats"]);
  // The second held-out test set, and the transfer recipe's training.
  EXPECT_NE(report.find("## The realistic test set"), std::string::npos) << report;
  EXPECT_NE(report.find("the transfer recipe"), std::string::npos) << report;
  const auto options = nlohmann::json::parse(read_text(out / "run" / "options.json"));
  EXPECT_EQ(options["train"].size(), 3u);
  EXPECT_EQ(options["people_size"], nlohmann::json::parse("[30.0, 256.0]"));
  EXPECT_TRUE(options.contains("pull_to_start"));
  EXPECT_EQ(options["distill"], 0.5);
  EXPECT_NE(report.find("(--distill 0.5)"), std::string::npos) << report;
  // WISE: the scored weights are the blend, and the report says so.
  EXPECT_TRUE(fs::exists(out / "run" / "wise.pt"));
  EXPECT_NE(report.find("pretrained + 0.5 × (fine-tuned − pretrained)"), std::string::npos)
      << report;
  // The size ablation: a row per subset (quick sizes 8 and 16) and the full set (24).
  EXPECT_NE(report.find("## Ablation: training-set size"), std::string::npos) << report;
  for (const char* row : {"| 8 | ", "| 16 | ", "| 24 | "})
    EXPECT_NE(report.find(row), std::string::npos) << row << "\n" << report;
  // Standing people mixed into training: both held-out sets scored for the three models.
  EXPECT_NE(report.find("## Keeping ordinary people"), std::string::npos) << report;
  for (const char* scored :
       {"test-finetuned-standing-mix.json", "standing-finetuned-standing-mix.json"})
    EXPECT_TRUE(fs::exists(out / scored)) << scored;
  EXPECT_EQ(count_of(report, "| fine-tuned, standing mixed in | "), 2u) << report;
  // ENSEMBLE: the fine-tuned column is the pretrained and the fine-tuned model together.
  EXPECT_NE(report.find("scored as an ensemble with the pretrained model"), std::string::npos)
      << report;

  // Scored again with FLIP=1 and the real photos at 256: training resumes as done, both columns
  // are scored mirrored too into their own files, and the report says so.
  const std::string again = "PULL=50 DISTILL=0.5 WISE=0.5 ENSEMBLE=1 FLIP=1 REAL_SIZE=256 bash " +
                            (source / "scripts" / "boost.sh").string() +
                            " --quick --recipe transfer --ranking " + ranking.string() +
                            " --real " + real.string() + " " + out.string() + " > " +
                            (dir / "log2.txt").string() + " 2>&1";
  ASSERT_EQ(std::system(again.c_str()), 0) << read_text(dir / "log2.txt");
  for (const char* scored : {"baseline-flip.json", "standing-baseline-flip.json",
                             "test-realistic-baseline-flip.json", "real-gt-baseline-flip-256.json"})
    EXPECT_TRUE(fs::exists(out / scored)) << scored;
  const std::string flipped = read_text(out / "report.md");
  EXPECT_NE(flipped.find("both columns scored with predict --flip"), std::string::npos) << flipped;
  EXPECT_NE(flipped.find("both columns at predict --size 256"), std::string::npos) << flipped;
  EXPECT_EQ(read_text(out / "run" / "train_log.csv"), train_log) << "training ran again";
}

}  // namespace
