// The model-boosting experiment end to end at its --quick size: scripts/boost.sh generates a
// training and a held-out test set, scores the pretrained model, fine-tunes it, scores it again
// (validating and keeping the best weights), scores both on people without wheelchairs
// (generated standing people and the real COCO sample), runs the training-set size ablation and
// writes the report as Markdown and HTML.

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "cli_runner.h"

namespace {

namespace fs = std::filesystem;
using wheelpose::testing::fresh_temp_dir;
using wheelpose::testing::read_text;
using wheelpose::testing::write_coco_sample_gt;

TEST(BoostScript, QuickRunWritesTheComparison) {
  if (!fs::exists(fs::path(WHEELPOSE_SOURCE_DIR) / "models" / "movenet-multipose.json")) {
    GTEST_SKIP() << "MoveNet models missing: run scripts/setup.sh";
  }
  const fs::path dir = fresh_temp_dir("boost_quick");
  fs::create_directories(dir / "real");
  const fs::path real = write_coco_sample_gt(dir / "real", /*copy_image=*/true);
  const fs::path out = dir / "run";
  const std::string command = "bash " + std::string(WHEELPOSE_SOURCE_DIR) +
                              "/scripts/boost.sh --quick --ablate --real " + real.string() + " " +
                              out.string() + " > " + (out.parent_path() / "log.txt").string() +
                              " 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << read_text(out.parent_path() / "log.txt");
  const std::string report = read_text(out / "report.md");
  EXPECT_NE(report.find("| KP AP | "), std::string::npos) << report;
  EXPECT_NE(report.find("| BB AP | "), std::string::npos) << report;
  EXPECT_NE(report.find("No clip is shared"), std::string::npos) << report;
  EXPECT_NE(report.find("wear clothes or hair training never drew"), std::string::npos) << report;
  EXPECT_NE(report.find("| Model | KP AP | KP AP50 |"), std::string::npos) << report;
  EXPECT_TRUE(fs::exists(out / "run" / "last.pt"));
  EXPECT_TRUE(fs::exists(out / "run" / "best.pt"));
  EXPECT_TRUE(fs::exists(out / "run" / "curves.png"));
  const std::string html = read_text(out / "report.html");
  EXPECT_NE(html.find("<img src=\"run/curves.png\">"), std::string::npos) << html;
  EXPECT_NE(html.find("<td> KP AP </td>"), std::string::npos) << html;
  EXPECT_TRUE(fs::exists(out / "finetuned.json"));
  // People without wheelchairs, generated and real, before and after.
  EXPECT_NE(report.find("## People without wheelchairs"), std::string::npos) << report;
  EXPECT_NE(report.find("Real people: 1 images"), std::string::npos) << report;
  for (const char* scored : {"standing-baseline.json", "standing-finetuned.json",
                             "real-baseline.json", "real-finetuned.json"})
    EXPECT_TRUE(fs::exists(out / scored)) << scored;
  // The size ablation: a row per subset (quick sizes 8 and 16) and the full set (24).
  EXPECT_NE(report.find("## Ablation: training-set size"), std::string::npos) << report;
  for (const char* row : {"| 8 | ", "| 16 | ", "| 24 | "})
    EXPECT_NE(report.find(row), std::string::npos) << row << "\n" << report;
}

}  // namespace
