// Golden-image tests: tiny fixed-seed scenes rendered and compared with reviewed references in
// tests/golden/render/<name>.png. On failure the actual, expected and diff images are written to
// $TMPDIR/wheelpose_golden_render/ and their paths printed; scripts/promote_golden.sh copies
// reviewed actual images over the references.

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "render/renderer.h"
#include "render/test_scenes.h"

namespace wheelpose::render {
namespace {

namespace fs = std::filesystem;

fs::path golden_dir() { return fs::path(WHEELPOSE_SOURCE_DIR) / "tests" / "golden" / "render"; }
fs::path failure_dir() { return fs::temp_directory_path() / "wheelpose_golden_render"; }

// Tolerant enough for other CPUs (Embree picks SSE/AVX code paths, which may flip a few edge
// pixels), strict enough that any visible change of lighting, texture or effect fails.
struct Difference {
  double mean = 0;         // mean absolute difference in 8-bit levels
  double large_share = 0;  // share of pixel channels off by more than 24 levels
};

Difference compare(const cv::Mat& a, const cv::Mat& b) {
  cv::Mat diff;
  cv::absdiff(a, b, diff);
  Difference d;
  d.mean = cv::mean(diff.reshape(1))[0];
  d.large_share = static_cast<double>(cv::countNonZero(diff.reshape(1) > 24)) /
                  static_cast<double>(diff.total() * 3);
  return d;
}

class Golden : public ::testing::TestWithParam<testing::NamedScene> {};

// 16 samples per pixel, 4 of which sample the lights (the rest reuse them), then denoised:
// the references exercise every part of decoupled shading.
constexpr RenderOptions kGoldenOptions{.spp = 16, .light_samples = 4};

TEST_P(Golden, MatchesTheReference) {
  const auto& named = GetParam();
  Renderer renderer(named.make());
  const cv::Mat actual_rgb = renderer.render(kGoldenOptions).rgb;
  cv::Mat actual;
  cv::cvtColor(actual_rgb, actual, cv::COLOR_RGB2BGR);
  const fs::path reference = golden_dir() / (std::string(named.name) + ".png");
  const cv::Mat expected = cv::imread(reference.string(), cv::IMREAD_COLOR);
  bool ok = !expected.empty() && expected.size() == actual.size();
  Difference d;
  if (ok) {
    d = compare(actual, expected);
    ok = d.mean <= 1.5 && d.large_share <= 0.01;
  }
  if (ok) return;
  fs::create_directories(failure_dir());
  const fs::path out = failure_dir() / named.name;
  cv::imwrite(out.string() + ".actual.png", actual);
  std::string report = "actual: " + out.string() + ".actual.png";
  if (!expected.empty()) {
    cv::imwrite(out.string() + ".expected.png", expected);
    report += "\nexpected: " + out.string() + ".expected.png";
    if (expected.size() == actual.size()) {
      cv::Mat diff;
      cv::absdiff(actual, expected, diff);
      cv::imwrite(out.string() + ".diff.png", diff * 4);
      report += "\ndiff (×4): " + out.string() + ".diff.png";
    }
  }
  ADD_FAILURE() << named.name << ": "
                << (expected.empty()
                        ? "no reference image " + reference.string()
                        : "differs: mean " + std::to_string(d.mean) + " levels, " +
                              std::to_string(100 * d.large_share) + "% channels off by > 24")
                << "\n"
                << report << "\nreview, then run scripts/promote_golden.sh to accept";
}

// The tolerance must not hide real changes: a 20 % dimmer sun fails against the reference.
TEST(GoldenTolerance, CatchesAVisibleLightingChange) {
  scene::Scene s = testing::lit_sphere();
  s.sun.intensity *= 0.8f;
  cv::Mat actual;
  cv::cvtColor(Renderer(s).render(kGoldenOptions).rgb, actual, cv::COLOR_RGB2BGR);
  const cv::Mat expected = cv::imread((golden_dir() / "lit_sphere.png").string(), cv::IMREAD_COLOR);
  ASSERT_FALSE(expected.empty());
  const Difference d = compare(actual, expected);
  EXPECT_TRUE(d.mean > 1.5 || d.large_share > 0.01) << d.mean << " " << d.large_share;
}

INSTANTIATE_TEST_SUITE_P(Render, Golden, ::testing::ValuesIn(testing::golden_scenes()),
                         [](const auto& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace wheelpose::render
