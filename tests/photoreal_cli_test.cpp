// End-to-end tests of the photo-real options of `wheelpose generate`: black-body lights, interior
// rooms, the phone camera's pipeline (recorded per image, JPEG at its drawn quality with 4:2:0
// chroma, shrunk-and-enlarged frames that keep their labels, the same bytes on one thread) and
// their bad values.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>

#include "cli_runner.h"

namespace {

using nlohmann::json;
using wheelpose::testing::fresh_temp_dir;
using wheelpose::testing::read_text;
using wheelpose::testing::run_wheelpose;
namespace fs = std::filesystem;

const char* kRoomScenario = R"(image: {width: 160, height: 120, spp: 1}
randomizers:
  Environment: {room_probability: 1.0}
  HumanGeneration: {min_per_frame: 1, max_per_frame: 2, pool_size: 4}
  Light: {color_temperature: {uniform: [2700, 6500]}, tint_probability: 0.05}
  Texture: {style: interior}
  HueOffset: {enabled: false}
)";

// The Y (first) component's sampling factors in the JPEG's start-of-frame segment: 0x22 for
// 4:2:0 (luma sampled twice as densely as chroma both ways).
int luma_sampling(const std::string& jpeg) {
  for (std::size_t i = 2; i + 10 < jpeg.size();) {
    if (static_cast<unsigned char>(jpeg[i]) != 0xff) return -1;
    const unsigned marker = static_cast<unsigned char>(jpeg[i + 1]);
    const std::size_t length =
        (static_cast<unsigned char>(jpeg[i + 2]) << 8) | static_cast<unsigned char>(jpeg[i + 3]);
    if (marker == 0xc0 || marker == 0xc2) return static_cast<unsigned char>(jpeg[i + 11]);
    i += 2 + length;
  }
  return -1;
}

TEST(PhotorealCli, PhoneCameraIsRecordedAndShapesTheFile) {
  const fs::path dir = fresh_temp_dir("photoreal_phone");
  const auto run = [&](const std::string& name, const std::string& phone) {
    const fs::path config = dir / (name + ".yaml");
    std::ofstream(config) << kRoomScenario << phone;
    const auto r = run_wheelpose("generate --config " + config.string() + " --out " +
                                 (dir / name).string() + " --frames 2 --seed 5");
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return json::parse(read_text(dir / name / "annotations.json"));
  };
  const json low = run(
      "low",
      "  PhoneCamera: {enabled: true, jpeg_quality: 50, rescale_probability: 1, rescale: 0.5}\n");
  const json high =
      run("high", "  PhoneCamera: {enabled: true, jpeg_quality: 95, rescale_probability: 0}\n");
  const json plain = run("plain", "");
  for (std::size_t i = 0; i < 2; ++i) {
    const json& phone = low["images"][i]["phone_camera"];
    EXPECT_EQ(phone["jpeg_quality"], 50);
    EXPECT_EQ(phone["rescale"], 0.5);
    EXPECT_TRUE(phone["filmic"].get<bool>());
    EXPECT_GE(phone["exposure_key"].get<double>(), 0.1);
    EXPECT_LE(phone["exposure_key"].get<double>(), 0.2);
    EXPECT_EQ(high["images"][i]["phone_camera"]["rescale"], 1.0);
    EXPECT_FALSE(plain["images"][i].contains("phone_camera"));
    const std::string file = low["images"][i]["file_name"];
    const std::string low_bytes = read_text(dir / "low" / "images" / file);
    const std::string high_bytes = read_text(dir / "high" / "images" / file);
    EXPECT_EQ(luma_sampling(low_bytes), 0x22);
    EXPECT_EQ(luma_sampling(high_bytes), 0x22);
    EXPECT_LT(low_bytes.size() * 2, high_bytes.size()) << "quality 50 of a half-size frame";
  }
  // The camera changes pixels, never labels: the same people in the same places.
  EXPECT_EQ(low["annotations"].size(), plain["annotations"].size());
  for (std::size_t a = 0; a < plain["annotations"].size(); ++a) {
    EXPECT_EQ(low["annotations"][a]["keypoints"], plain["annotations"][a]["keypoints"]);
  }
  // Noise, exposure and resampling are seeded per frame: one thread gives the same bytes.
  const fs::path config = dir / "low.yaml";
  const auto single = run_wheelpose("generate --config " + config.string() + " --out " +
                                    (dir / "low1").string() + " --frames 2 --seed 5 --threads 1");
  ASSERT_EQ(single.exit_code, 0) << single.output;
  for (std::size_t i = 0; i < 2; ++i) {
    const std::string file = low["images"][i]["file_name"];
    EXPECT_EQ(read_text(dir / "low1" / "images" / file), read_text(dir / "low" / "images" / file));
  }
  // Recorded in scenario.json with the settings used.
  const json scenario = json::parse(read_text(dir / "low" / "scenario.json"));
  EXPECT_NE(scenario.dump().find("\"rescale_probability\":1.0"), std::string::npos);
}

// Outdoor frames are recorded as such; the frames that stay rooms are the same bytes as in a
// scenario without outdoor frames (the outdoor draws come after every other).
TEST(PhotorealCli, OutdoorFramesAreRecordedAndRoomsKeepTheirBytes) {
  const fs::path dir = fresh_temp_dir("photoreal_outdoor");
  std::string outdoor = kRoomScenario;
  const std::string rooms_only = "Environment: {room_probability: 1.0}";
  outdoor.replace(outdoor.find(rooms_only), rooms_only.size(),
                  "Environment: {room_probability: 1.0, outdoor_probability: 0.5}");
  const auto run = [&](const std::string& name, const std::string& scenario) {
    std::ofstream(dir / (name + ".yaml")) << scenario;
    const auto r = run_wheelpose("generate --config " + (dir / (name + ".yaml")).string() +
                                 " --out " + (dir / name).string() + " --frames 6 --seed 4");
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return json::parse(read_text(dir / name / "annotations.json"));
  };
  const json rooms = run("rooms", kRoomScenario);
  const json mixed = run("mixed", outdoor);
  int outdoors = 0, kept = 0;
  for (std::size_t i = 0; i < mixed["images"].size(); ++i) {
    const std::string file = mixed["images"][i]["file_name"];
    EXPECT_EQ(rooms["images"][i]["environment"], "room");
    if (mixed["images"][i]["environment"] == "outdoor") {
      ++outdoors;
      continue;
    }
    EXPECT_EQ(mixed["images"][i]["environment"], "room");
    EXPECT_EQ(read_text(dir / "mixed" / "images" / file),
              read_text(dir / "rooms" / "images" / file))
        << file;
    ++kept;
  }
  EXPECT_GT(outdoors, 0);
  EXPECT_GT(kept, 0);
}

// Coats on hangers in every room: the catalogue is recorded (only when they are drawn) and they
// show in the frames.
TEST(PhotorealCli, HangingClothesAreDrawnInRoomsAndRecorded) {
  const fs::path dir = fresh_temp_dir("photoreal_clothes");
  const auto run = [&](const std::string& name, const std::string& scenario) {
    std::ofstream(dir / (name + ".yaml")) << scenario;
    const auto r = run_wheelpose("generate --config " + (dir / (name + ".yaml")).string() +
                                 " --out " + (dir / name).string() + " --frames 4 --seed 6");
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return json::parse(read_text(dir / name / "scenario.json"));
  };
  const json plain = run("plain", kRoomScenario);
  const json clothes =
      run("clothes", std::string(kRoomScenario) +
                         "  HangingClothes: {enabled: true, min_count: 2, max_count: 2}\n");
  EXPECT_FALSE(plain.contains("hanging_clothes"));
  if (clothes["hanging_clothes"]["models"] == 0) GTEST_SKIP() << "KatorLegaz.sh3f not installed";
  EXPECT_EQ(clothes["hanging_clothes"]["models"], 2);
  int differ = 0;
  for (const auto& file : fs::directory_iterator(dir / "plain" / "images")) {
    differ +=
        read_text(file.path()) != read_text(dir / "clothes" / "images" / file.path().filename());
  }
  EXPECT_GT(differ, 0);
}

// Motion blur: the same frames with the shutter open 0.1 s differ only around people (their
// streaks reach at most 32 px either side, a JPEG block beyond), and the labels are the same.
TEST(PhotorealCli, AnOpenShutterBlursOnlyAroundPeopleAndKeepsTheLabels) {
  const fs::path dir = fresh_temp_dir("photoreal_shutter");
  const auto run = [&](const std::string& name, const std::string& shutter) {
    const fs::path config = dir / (name + ".yaml");
    std::ofstream(config) << "image: {width: 320, height: 240, spp: 1}\n"
                          << "randomizers:\n"
                          << "  Environment: {room_probability: 1.0}\n"
                          << "  HumanGeneration: {min_per_frame: 2, max_per_frame: 2}\n"
                          << "  PostProcessVolume: {enabled: false}\n"
                          << "  PhoneCamera: {enabled: true, shot_noise: 0, read_noise: 0, "
                          << "rescale_probability: 0, jpeg_quality: 95, shutter: " << shutter
                          << "}\n";
    const auto r = run_wheelpose("generate --config " + config.string() + " --out " +
                                 (dir / name).string() + " --frames 3 --seed 8");
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return json::parse(read_text(dir / name / "annotations.json"));
  };
  const json still = run("still", "0");
  const json blurred = run("blurred", "0.1");
  ASSERT_EQ(blurred["annotations"].size(), still["annotations"].size());
  for (std::size_t a = 0; a < still["annotations"].size(); ++a) {
    EXPECT_EQ(blurred["annotations"][a]["keypoints"], still["annotations"][a]["keypoints"]);
    EXPECT_EQ(blurred["annotations"][a]["bbox"], still["annotations"][a]["bbox"]);
  }
  int changed = 0;
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(blurred["images"][i]["phone_camera"]["shutter"], 0.1);
    const std::string file = still["images"][i]["file_name"];
    const cv::Mat a = cv::imread((dir / "still" / "images" / file).string());
    const cv::Mat b = cv::imread((dir / "blurred" / "images" / file).string());
    ASSERT_FALSE(a.empty());
    ASSERT_EQ(a.size(), b.size());
    cv::Mat near_people = cv::Mat::zeros(a.size(), CV_8U);
    for (const json& ann : still["annotations"]) {
      if (ann["image_id"] != still["images"][i]["id"]) continue;
      const auto box = ann["bbox_amodal"].get<std::vector<double>>();
      const int reach = 32 + 32;  // the streak, and a chair or JPEG block beyond the body
      cv::Rect around(static_cast<int>(box[0]) - reach, static_cast<int>(box[1]) - reach,
                      static_cast<int>(box[2]) + 2 * reach, static_cast<int>(box[3]) + 2 * reach);
      near_people(around & cv::Rect(0, 0, a.cols, a.rows)).setTo(255);
    }
    cv::Mat difference, differ;
    cv::absdiff(a, b, difference);
    cv::transform(difference, differ, cv::Matx13f(1, 1, 1));
    changed += cv::countNonZero(differ);
    const cv::Mat far_from_people = differ & ~near_people;
    EXPECT_EQ(cv::countNonZero(far_from_people), 0) << file;
  }
  EXPECT_GT(changed, 50) << "people in clips move during a 0.1 s shutter";
}

TEST(PhotorealCli, BadValuesNameTheKey) {
  const fs::path dir = fresh_temp_dir("photoreal_bad");
  const struct {
    std::string yaml, expected;
  } cases[] = {
      {"  Light: {color_temperature: {uniform: [1000, 6500]}}\n", "color_temperature"},
      {"  PhoneCamera: {enabled: true, jpeg_quality: 101}\n", "jpeg_quality"},
      {"  PhoneCamera: {enabled: true, rescale: 0}\n", "rescale"},
      {"  PhoneCamera: {enabled: true, shutter: 0.5}\n", "shutter"},
      {"  Texture: {style: plaid}\n", "'plaid' is not one of: paper, interior"},
      {"  HumanGeneration: {garment_colours: neon}\n", "'neon' is not one of: palette, uniform"},
      {"  HumanGeneration: {hair_strand_coverage: 0}\n", "hair_strand_coverage"},
      {"  Wheelchair: {colours: neon}\n", "'neon' is not one of: palette, uniform"},
      {"  EmptyWheelchair: {colours: 3}\n", "'3' is not one of: palette, uniform"},
      {"  Environment: {outdoor_probability: 1.5}\n", "outdoor_probability"},
      {"  Statue: {enabled: true, min_count: 3, max_count: 1}\n", "max_count is below min_count"},
      {"  HangingClothes: {enabled: true, min_count: 2, max_count: 1}\n",
       "max_count is below min_count"},
  };
  for (const auto& c : cases) {
    const fs::path config = dir / "bad.yaml";
    std::ofstream(config) << "randomizers:\n" << c.yaml;
    const auto r = run_wheelpose("generate --config " + config.string() + " --out " +
                                 (dir / "out").string() + " --frames 1");
    EXPECT_EQ(r.exit_code, 2) << c.yaml << r.output;
    EXPECT_NE(r.output.find("bad.yaml:2"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(c.expected), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir / "out")) << c.yaml;
  }
}

}  // namespace
