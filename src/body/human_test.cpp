#include "body/human.h"

#include <gtest/gtest.h>

#include <fstream>

#include "body/assets.h"
#include "body/test_data.h"
#include "core/error.h"

namespace wheelpose::body {
namespace {

double sum_with_prefix(const TargetWeights& w, const std::string& prefix) {
  double s = 0;
  for (const auto& [name, x] : w) {
    if (name.rfind(prefix, 0) == 0) s += x;
  }
  return s;
}

const std::map<std::string, MacroBreakpoints>& breakpoints() {
  return testing::body_data().model().breakpoints();
}

TEST(MacroWeights, AgeSliderMatchesMakeHumanScale) {
  EXPECT_DOUBLE_EQ(age_slider(1), 0.0);
  EXPECT_DOUBLE_EQ(age_slider(11), 0.1875);
  EXPECT_DOUBLE_EQ(age_slider(25), 0.5);
  EXPECT_DOUBLE_EQ(age_slider(90), 1.0);
  EXPECT_DOUBLE_EQ(age_slider(57.5), 0.75);
  EXPECT_DOUBLE_EQ(age_slider(100), 1.0);
}

TEST(MacroWeights, BreakpointsSnapToMakeHumanValues) {
  const auto& age = breakpoints().at("age");
  ASSERT_EQ(age.at.size(), 4u);
  EXPECT_DOUBLE_EQ(age.at[1], 0.1875);
  EXPECT_EQ(age.names[3], "old");
  const auto& height = breakpoints().at("height");
  EXPECT_EQ(height.names, (std::vector<std::string>{"minheight", "", "maxheight"}));
  EXPECT_DOUBLE_EQ(height.at[1], 0.5);
}

TEST(MacroWeights, UniversalAndEthnicWeightsSumToOne) {
  for (double g : {0.0, 0.3, 1.0}) {
    for (double age : {10.0, 18.0, 40.0, 100.0}) {
      MacroParams p;
      p.gender = g;
      p.age_years = age;
      p.muscle = 0.2;
      p.weight = 0.9;
      p.african = 0.2;
      p.asian = 0.5;
      p.caucasian = 0.3;
      const TargetWeights w = macro_target_weights(p, breakpoints());
      EXPECT_NEAR(sum_with_prefix(w, "universal-"), 1.0, 1e-12);
      EXPECT_NEAR(sum_with_prefix(w, "african-") + sum_with_prefix(w, "asian-") +
                      sum_with_prefix(w, "caucasian-"),
                  1.0, 1e-12);
      EXPECT_NEAR(sum_with_prefix(w, "asian-"), 0.5, 1e-12);
    }
  }
}

TEST(MacroWeights, CornerHitsExactlyOneTarget) {
  MacroParams p;
  p.gender = 1.0;
  p.age_years = 25;
  p.muscle = 0.5;
  p.weight = 0.5;
  p.height = 0.5;
  p.proportions = 0.5;
  p.african = 0;
  p.asian = 0;
  p.caucasian = 1;
  const TargetWeights w = macro_target_weights(p, breakpoints());
  ASSERT_EQ(w.size(), 2u);
  EXPECT_DOUBLE_EQ(w.at("universal-male-young-averagemuscle-averageweight"), 1.0);
  EXPECT_DOUBLE_EQ(w.at("caucasian-male-young"), 1.0);
  // Max height at the same corner: one height target with weight 1.
  p.height = 1.0;
  const TargetWeights h = macro_target_weights(p, breakpoints());
  EXPECT_DOUBLE_EQ(h.at("height/male-young-averagemuscle-averageweight-maxheight"), 1.0);
  EXPECT_EQ(h.size(), 3u);
}

TEST(MacroWeights, MidpointBlendsNeighbours) {
  MacroParams p;
  p.gender = 0.25;
  p.age_years = 25;
  p.muscle = 0.75;
  const TargetWeights w = macro_target_weights(p, breakpoints());
  EXPECT_DOUBLE_EQ(w.at("universal-female-young-averagemuscle-averageweight"), 0.75 * 0.5);
  EXPECT_DOUBLE_EQ(w.at("universal-male-young-maxmuscle-averageweight"), 0.25 * 0.5);
}

TEST(MacroParamsTest, RejectsBadOverrides) {
  MacroParams p;
  EXPECT_THROW(p.set("age", "5"), Error);
  EXPECT_THROW(p.set("gender", "1.5"), Error);
  EXPECT_THROW(p.set("gender", "abc"), Error);
  EXPECT_THROW(p.set("shoe_size", "3"), Error);
  p.set("age", "70");
  EXPECT_DOUBLE_EQ(p.age_years, 70);
}

TEST(TargetParse, ReadsLinesAndRejectsGarbage) {
  const SparseTarget t = parse_target("# c\n3 0.5 -1 2\n\n7 1e-1 0 0\n", 10, "x.target");
  ASSERT_EQ(t.index.size(), 2u);
  EXPECT_EQ(t.index[1], 7);
  EXPECT_FLOAT_EQ(t.delta[0].y(), -1.0f);
  EXPECT_THROW(parse_target("3 0.5 x 2\n", 10, "x.target"), Error);
  EXPECT_THROW(parse_target("12 0 0 0\n", 10, "x.target"), Error);
}

TEST(Morph, MaleTallerThanFemaleAndChildSmaller) {
  const HumanModel& model = testing::body_data().model();
  auto stature = [&](double gender, double age) {
    MacroParams p;
    p.gender = gender;
    p.age_years = age;
    const auto v = model.morph(p);
    float lo = 1e9f, hi = -1e9f;
    for (int i : testing::body_data().body_vertices()) {
      lo = std::min(lo, v[i].y());
      hi = std::max(hi, v[i].y());
    }
    return hi - lo;
  };
  const float male = stature(1, 25), female = stature(0, 25), child = stature(0.5, 10);
  EXPECT_GT(male, female);
  EXPECT_GT(male, 1.6f);
  EXPECT_LT(male, 2.0f);
  EXPECT_LT(child, female - 0.1f);
}

TEST(Assets, MissingDirectoryNamesTheFile) {
  try {
    locate_assets(std::filesystem::path("/nonexistent/assets"));
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("base.obj"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("setup.sh"), std::string::npos);
  }
  EXPECT_THROW(read_asset("/nonexistent/x.target.gz"), Error);
}

TEST(Assets, CorruptGzipIsReported) {
  const auto path = std::filesystem::temp_directory_path() / "wheelpose_body_corrupt.target.gz";
  {
    std::ofstream out(path, std::ios::binary);
    const std::string bytes("\x1f\x8b\x08\x00\x00\x00\x00\x00\x00\x03garbage", 17);
    out << bytes;
  }
  EXPECT_THROW(read_asset(path), Error);
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace wheelpose::body

namespace wheelpose::body {
namespace {

// The ramp passes through its documented anchors (8-bit sRGB decoded to linear) and gets
// lighter all the way.
TEST(SkinColour, PassesThroughTheDocumentedSwatchesAndLightens) {
  const auto linear = [](int v) {
    const double c = v / 255.0;
    return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
  };
  const Eigen::Vector3f darkest = skin_colour(0.0), dark_skin = skin_colour(0.3),
                        light_skin = skin_colour(0.65), lightest = skin_colour(1.0);
  EXPECT_NEAR(darkest.x(), linear(41), 1e-6);      // Monk MST-10
  EXPECT_NEAR(dark_skin.y(), linear(82), 1e-6);    // ColorChecker dark skin
  EXPECT_NEAR(light_skin.z(), linear(130), 1e-6);  // ColorChecker light skin
  EXPECT_NEAR(lightest.x(), linear(243), 1e-6);    // Monk MST-2
  float last = -1;
  for (double t = 0; t <= 1.0001; t += 0.05) {
    const Eigen::Vector3f c = skin_colour(t);
    const float luminance = 0.2126f * c.x() + 0.7152f * c.y() + 0.0722f * c.z();
    EXPECT_GT(luminance, last) << t;
    EXPECT_GE(c.x(), c.z()) << t;  // skin is redder than it is blue
    last = luminance;
  }
  EXPECT_EQ(skin_colour(-1), darkest);
  EXPECT_EQ(skin_colour(2), lightest);
}

}  // namespace
}  // namespace wheelpose::body
