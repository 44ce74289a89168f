// End-to-end tests of `wheelpose body`.

#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <set>

#include "cli_runner.h"

namespace wheelpose::testing {
namespace {

const std::string kAssets = std::string(" --assets ") + WHEELPOSE_SHARED_DIR + "/assets";

TEST(BodyCli, ExportWritesGlbAndJsonDeterministically) {
  const auto dir = fresh_temp_dir("body_export");
  const auto a = dir / "a.glb", b = dir / "b.glb";
  for (const auto& out : {a, b}) {
    const CliResult r = run_wheelpose(
        "body export --seed 5 --params age=70 wheelchair=sport --out " + out.string() + kAssets);
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  const std::string glb = read_text(a);
  ASSERT_GT(glb.size(), 100000u);
  EXPECT_EQ(glb.substr(0, 4), "glTF");
  EXPECT_EQ(glb, read_text(b));
  const auto json = nlohmann::json::parse(read_text(dir / "a.json"));
  EXPECT_DOUBLE_EQ(json["params"]["age"].get<double>(), 70.0);
  EXPECT_EQ(json["wheelchair"]["type"], "sport");
  EXPECT_EQ(json["coco_keypoints"].size(), 17u);
}

TEST(BodyCli, SampleWritesCountPeople) {
  const auto dir = fresh_temp_dir("body_sample");
  const CliResult r =
      run_wheelpose("body sample --count 2 --seed 3 --out " + dir.string() + kAssets);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_FALSE(read_text(dir / "person_0000.glb").empty());
  EXPECT_FALSE(read_text(dir / "person_0001.json").empty());
  EXPECT_NE(read_text(dir / "person_0000.json"), read_text(dir / "person_0001.json"));
  // Dressed from the installed proxies, and pictured on a contact sheet (2 people: 2 x 1 tiles).
  const auto description = nlohmann::json::parse(read_text(dir / "person_0000.json"));
  EXPECT_GE(description["proxies"].size(), 3u);
  const cv::Mat sheet = cv::imread((dir / "contact_sheet.png").string(), cv::IMREAD_COLOR);
  ASSERT_FALSE(sheet.empty());
  EXPECT_EQ(sheet.cols, 512);
  EXPECT_EQ(sheet.rows, 256);
  // Each tile shows somebody: not a flat grey picture.
  for (int tile = 0; tile < 2; ++tile) {
    cv::Scalar mean, stddev;
    cv::meanStdDev(sheet(cv::Rect(256 * tile, 0, 256, 256)), mean, stddev);
    EXPECT_GT(stddev[0], 10.0);
  }
}

TEST(BodyCli, BadInputsExitTwoWithOneLine) {
  const auto dir = fresh_temp_dir("body_bad");
  CliResult r = run_wheelpose("body export --seed 1 --params age=300 --out " +
                              (dir / "x.glb").string() + kAssets);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("age"), std::string::npos);
  r = run_wheelpose("body export --seed 1 --out " + (dir / "x.glb").string() +
                    " --assets /nonexistent");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("base.obj"), std::string::npos);
  r = run_wheelpose("body export --seed 1 --clip /nonexistent.json --out " +
                    (dir / "x.glb").string() + kAssets);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  r = run_wheelpose("body export --empty-wheelchair --params wheelchair=none --out " +
                    (dir / "x.glb").string() + kAssets);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("nothing to export"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "x.glb"));
}

TEST(BodyCli, EmptyWheelchair) {
  const auto dir = fresh_temp_dir("body_empty");
  const CliResult r = run_wheelpose(
      "body export --seed 2 --empty-wheelchair --params "
      "wheelchair=power --out " +
      (dir / "chair.glb").string() + kAssets);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(read_text(dir / "chair.glb").substr(0, 4), "glTF");
  const CliResult cc =
      run_wheelpose("body export --cc-by-wheelchair --out " + (dir / "cc.glb").string());
  ASSERT_EQ(cc.exit_code, 0) << cc.output;
  EXPECT_NE(cc.output.find("bgamage"), std::string::npos);
  EXPECT_GT(read_text(dir / "cc.glb").size(), 100000u);
}

}  // namespace
}  // namespace wheelpose::testing

namespace wheelpose::testing {
namespace {

TEST(BodyCli, PosesPersonByASeatedClipFrame) {
  const auto dir = fresh_temp_dir("body_clip");
  const std::string bvh = std::string(WHEELPOSE_SHARED_DIR) + "/data/bvh/131_01.bvh";
  CliResult r =
      run_wheelpose("motion convert " + bvh + " --out " + dir.string() + " --exports json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string clip = (dir / "131_01.json").string();
  std::vector<nlohmann::json> wrists;
  std::vector<cv::Mat> portraits;
  for (int frame : {0, 60}) {
    const auto out = dir / ("f" + std::to_string(frame) + ".glb");
    const auto portrait = dir / ("f" + std::to_string(frame) + ".png");
    r = run_wheelpose("body export --seed 1 --clip " + clip + " --frame " + std::to_string(frame) +
                      " --out " + out.string() + " --portrait " + portrait.string() + kAssets);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    auto json = nlohmann::json::parse(read_text(dir / ("f" + std::to_string(frame) + ".json")));
    wrists.push_back(json["coco_keypoints"]["left_wrist"]);
    portraits.push_back(cv::imread(portrait.string(), cv::IMREAD_COLOR));
    ASSERT_EQ(portraits.back().size(), cv::Size(512, 512));
    cv::Scalar mean, stddev;
    cv::meanStdDev(portraits.back(), mean, stddev);
    EXPECT_GT(stddev[0], 10.0);  // somebody is in the picture
  }
  EXPECT_NE(wrists[0], wrists[1]);                                    // the arm moves with the clip
  EXPECT_GT(cv::norm(portraits[0], portraits[1], cv::NORM_L1), 0.0);  // and so does the picture
  r = run_wheelpose("body export --seed 1 --clip " + clip + " --frame 100000 --out " +
                    (dir / "x.glb").string() + kAssets);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  r = run_wheelpose("body export --rigged --clip " + clip + " --portrait " +
                    (dir / "x.png").string() + " --out " + (dir / "x.glb").string() + kAssets);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "x.png"));
}

}  // namespace
}  // namespace wheelpose::testing

namespace wheelpose::testing {
namespace {

// The JSON chunk of a .glb.
nlohmann::json glb_json(const std::string& glb) {
  auto u32 = [&glb](std::size_t at) {
    return static_cast<std::uint32_t>(static_cast<unsigned char>(glb[at])) |
           static_cast<std::uint32_t>(static_cast<unsigned char>(glb[at + 1])) << 8 |
           static_cast<std::uint32_t>(static_cast<unsigned char>(glb[at + 2])) << 16 |
           static_cast<std::uint32_t>(static_cast<unsigned char>(glb[at + 3])) << 24;
  };
  return nlohmann::json::parse(glb.substr(20, u32(12)));
}

// The first `frames` frames of the CMU clip as a seated clip JSON.
std::filesystem::path short_clip(const std::filesystem::path& dir, std::size_t frames) {
  const std::string bvh = std::string(WHEELPOSE_SHARED_DIR) + "/data/bvh/131_01.bvh";
  const CliResult r =
      run_wheelpose("motion convert " + bvh + " --out " + dir.string() + " --exports json");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  auto clip = nlohmann::json::parse(read_text(dir / "131_01.json"));
  for (const char* key : {"root_positions", "local_rotations", "positions"}) {
    auto& values = clip[key];
    values.erase(values.begin() + static_cast<long>(std::min(frames, values.size())), values.end());
  }
  clip["frame_count"] = frames;
  const auto path = dir / ("short_" + std::to_string(frames) + ".json");
  std::ofstream(path) << clip.dump();
  return path;
}

TEST(BodyCli, RiggedExportAnimatesTheSkinnedPersonByTheClip) {
  const auto dir = fresh_temp_dir("body_rigged");
  const std::string clip = short_clip(dir, 24).string();
  const std::string args = "body export --rigged --seed 4 --clip " + clip +
                           " --params mobility_aid=cane wear=clothes/shoes01 wear=hair/short02";
  for (const char* name : {"a.glb", "b.glb"}) {
    const CliResult r = run_wheelpose(args + " --out " + (dir / name).string() + kAssets);
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  const std::string glb = read_text(dir / "a.glb");
  EXPECT_EQ(glb, read_text(dir / "b.glb"));  // same input, same bytes
  const nlohmann::json gltf = glb_json(glb);
  ASSERT_EQ(gltf["skins"].size(), 1u);
  EXPECT_EQ(gltf["skins"][0]["joints"].size(), 53u);
  ASSERT_EQ(gltf["animations"].size(), 1u);
  const auto& animation = gltf["animations"][0];
  EXPECT_EQ(animation["channels"].size(), 53u + 1u);  // every rotation, the root's translation
  for (const auto& sampler : animation["samplers"]) {
    EXPECT_EQ(sampler["interpolation"], "LINEAR");
    const auto& times = gltf["accessors"][sampler["input"].get<int>()];
    EXPECT_EQ(times["count"], 24);
    EXPECT_NEAR(times["max"][0].get<double>(), 23.0 / 120.0, 1e-6);
  }
  // Body, shoes, hair and the cane skinned; the chair's parts under the person's node.
  std::set<std::string> skinned, under_person;
  for (const auto& node : gltf["nodes"])
    if (node.contains("skin")) skinned.insert(node["name"].get<std::string>());
  for (int child : gltf["nodes"][0]["children"])
    under_person.insert(gltf["nodes"][child]["name"].get<std::string>());
  for (const char* name :
       {"body_node", "shoes01_node", "short02_node", "mobility_aid_hand_r_frame_node"})
    EXPECT_EQ(skinned.count(name), 1u) << name;
  EXPECT_EQ(under_person.count("wheelchair_frame_node"), 1u);
  EXPECT_EQ(under_person.count("Root"), 1u);
  // The description beside it is the first frame's person.
  const auto json = nlohmann::json::parse(read_text(dir / "a.json"));
  EXPECT_EQ(json["coco_keypoints"].size(), 17u);
  // The same person as binary FBX, chosen by the extension (rigged_fbx_test.cpp checks its
  // content; tests/blender imports it).
  const CliResult r = run_wheelpose(args + " --out " + (dir / "a.fbx").string() + kAssets);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(read_text(dir / "a.fbx").substr(0, 20), "Kaydara FBX Binary  ");
}

TEST(BodyCli, RiggedExportRefusesBadInputWithoutWritingAFile) {
  const auto dir = fresh_temp_dir("body_rigged_bad");
  const auto out = dir / "x.glb";
  const std::string clip = short_clip(dir, 0).string();
  CliResult r = run_wheelpose("body export --rigged --out " + out.string() + kAssets);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--rigged needs --clip"), std::string::npos) << r.output;
  r = run_wheelpose("body export --rigged --clip " + clip + " --out " + out.string() + kAssets);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("no frames"), std::string::npos) << r.output;
  r = run_wheelpose("body export --rigged --clip " + clip + " --frame 3 --out " + out.string() +
                    kAssets);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  r = run_wheelpose("body export --rigged --clip /nonexistent.json --out " + out.string() +
                    kAssets);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  r = run_wheelpose("body export --rigged --clip " + short_clip(dir, 4).string() + " --out " +
                    (dir / "x.obj").string() + kAssets);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("must end in .glb or .fbx"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "x.obj"));
  EXPECT_FALSE(std::filesystem::exists(out));
  EXPECT_FALSE(std::filesystem::exists(dir / "x.json"));
}

}  // namespace
}  // namespace wheelpose::testing
