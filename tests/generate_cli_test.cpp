// End-to-end tests of `wheelpose generate`: labels checked against the ground-truth maps,
// determinism across thread counts, shard merge, kill-and-resume, clip selection and errors.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <set>
#include <string>
#include <vector>

#include "cli_runner.h"
#include "core/cpu_isa.h"
#include "core/isa_test_environment.h"

namespace {

using nlohmann::json;
using wheelpose::testing::fresh_temp_dir;
using wheelpose::testing::read_text;
using wheelpose::testing::run_killed_until_done;
using wheelpose::testing::run_wheelpose;
namespace fs = std::filesystem;

json read_json(const fs::path& path) { return json::parse(read_text(path)); }

// A small, busy scenario: 160x120, 1 spp, people close to the camera so most are visible and
// overlap (occlusion by other people, chairs and occluders is exercised).
const char* kSmallScenario = R"(image: {width: 160, height: 120, spp: 1}
labels: {ground_truth_maps: true, min_visible_pixels: 20}
randomizers:
  HumanGeneration: {min_per_frame: 3, max_per_frame: 5, pool_size: 8}
  TransformPlacement: {x: {uniform: [-2, 2]}, y: {uniform: [-1.5, 1.5]}, size: {uniform: [0.8, 1.5]}}
  BackgroundOccluderScale: {scale: {uniform: [0.5, 2]}}
  Camera: {field_of_view: {uniform: [25, 40]}}
  LimbDifference: {probability: 0.3}
)";

fs::path write_scenario(const fs::path& dir) {
  const fs::path path = dir / "small.yaml";
  std::ofstream(path) << kSmallScenario;
  return path;
}

std::string generate_args(const fs::path& config, const fs::path& out, int frames,
                          const std::string& extra = "") {
  return "generate --config " + config.string() + " --out " + out.string() + " --frames " +
         std::to_string(frames) + " --seed 7 --format png " + extra;
}

// Every file under `dir` (relative path → bytes), for byte-identity comparisons.
std::map<std::string, std::string> tree(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (e.is_regular_file()) files[fs::relative(e.path(), dir).string()] = read_text(e.path());
  }
  return files;
}

const std::vector<double> kTolerance = {0.05, 0.045, 0.045, 0.05, 0.05, 0.185, 0.185, 0.15, 0.15,
                                        0.15, 0.15,  0.21,  0.21, 0.15, 0.15,  0.15,  0.15};

TEST(GenerateCli, LabelsAgreeWithTheGroundTruthMaps) {
  const fs::path dir = fresh_temp_dir("generate_labels");
  const auto r = run_wheelpose(generate_args(write_scenario(dir), dir / "out", 6));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json coco = read_json(dir / "out" / "annotations.json");
  ASSERT_EQ(coco["images"].size(), 6u);
  ASSERT_GT(coco["annotations"].size(), 6u) << "the scenario should show several people";
  std::map<int, json> images;
  for (const json& im : coco["images"]) images[im["id"].get<int>()] = im;
  int checked_visible = 0, checked_occluded = 0, absent = 0;
  for (const json& a : coco["annotations"]) {
    const json& im = images.at(a["image_id"].get<int>());
    const std::string stem = im["file_name"].get<std::string>().substr(0, 6);
    const cv::Mat instance = cv::imread((dir / "out" / "maps" / (stem + "_instance.png")).string(),
                                        cv::IMREAD_UNCHANGED);
    const cv::Mat depth =
        cv::imread((dir / "out" / "maps" / (stem + "_depth.png")).string(), cv::IMREAD_UNCHANGED);
    ASSERT_FALSE(instance.empty());
    ASSERT_FALSE(depth.empty());
    const cv::Mat mask = instance == a["instance_id"].get<int>();
    // area = visible mask pixels; bbox = tight box of the mask (grown to visible keypoints).
    EXPECT_EQ(a["area"].get<int>(), cv::countNonZero(mask));
    const cv::Rect tight = cv::boundingRect(mask);
    const auto box = a["bbox"].get<std::vector<double>>();
    EXPECT_LE(box[0], tight.x);
    EXPECT_LE(box[1], tight.y);
    EXPECT_GE(box[0] + box[2], tight.x + tight.width);
    EXPECT_GE(box[1] + box[3], tight.y + tight.height);
    const auto& in = im["camera"]["intrinsics"];
    const double fx = in["fx"], fy = in["fy"], cx = in["cx"], cy = in["cy"];
    const auto kp = a["keypoints"].get<std::vector<double>>();
    const auto k3 = a["keypoints_3d"].get<std::vector<double>>();
    ASSERT_EQ(kp.size(), 51u);
    ASSERT_EQ(k3.size(), 51u);
    int labelled = 0;
    const double scale = a["scale"];
    for (int k = 0; k < 17; ++k) {
      const double x = kp[3 * k], y = kp[3 * k + 1];
      const int v = static_cast<int>(kp[3 * k + 2]);
      if (v == 0) {
        EXPECT_EQ(x, 0);
        EXPECT_EQ(y, 0);
        ++absent;
        continue;
      }
      ++labelled;
      // The 3D keypoint (camera space, looking down -Z) projects onto the 2D one.
      const double X = k3[3 * k], Y = k3[3 * k + 1], Z = k3[3 * k + 2];
      ASSERT_LT(Z, 0);
      EXPECT_NEAR(cx + fx * X / -Z, x, 0.5);
      EXPECT_NEAR(cy - fy * Y / -Z, y, 0.5);
      // Depth map (millimetres) at the keypoint's pixel against keypoint depth and tolerance;
      // 1.5 mm covers the map's rounding.
      const double surface =
          depth.at<std::uint16_t>(static_cast<int>(y), static_cast<int>(x)) / 1000.0;
      const double limit = -Z - kTolerance[k] * scale;
      if (v == 2) {
        EXPECT_TRUE(surface == 0 || surface >= limit - 0.0015) << "keypoint " << k;
        // The box holds the visible keypoints (occluded ones may lie outside the visible mask).
        EXPECT_GE(x, box[0]);
        EXPECT_GE(y, box[1]);
        EXPECT_LE(x, box[0] + box[2]);
        EXPECT_LE(y, box[1] + box[3]);
        ++checked_visible;
      } else {
        EXPECT_GT(surface, 0);
        EXPECT_LT(surface, limit + 0.0015) << "keypoint " << k;
        ++checked_occluded;
      }
    }
    EXPECT_EQ(a["num_keypoints"].get<int>(), labelled);
    EXPECT_GE(a["visible_fraction"].get<double>(), 0.0);
    EXPECT_LE(a["visible_fraction"].get<double>(), 1.0);
    EXPECT_TRUE(a.contains("wheelchair_type"));
    EXPECT_TRUE(a.contains("motion_id"));
    EXPECT_FALSE(a["segmentation"].empty());
  }
  EXPECT_GT(checked_visible, 20);
  EXPECT_GT(checked_occluded, 5) << "people, chairs and occluders should hide some keypoints";
  EXPECT_GT(absent, 0);
  const auto v = run_wheelpose("coco validate " + (dir / "out" / "annotations.json").string() +
                               " --images " + (dir / "out" / "images").string());
  EXPECT_EQ(v.exit_code, 0) << v.output;
}

TEST(GenerateCli, SameBytesWhateverTheThreadCount) {
  const fs::path dir = fresh_temp_dir("generate_threads");
  const fs::path config = write_scenario(dir);
  ASSERT_EQ(run_wheelpose(generate_args(config, dir / "one", 4, "--threads 1")).exit_code, 0);
  ASSERT_EQ(run_wheelpose(generate_args(config, dir / "two", 4, "--threads 2")).exit_code, 0);
  const auto one = tree(dir / "one"), two = tree(dir / "two");
  EXPECT_EQ(one.size(), two.size());
  for (const auto& [name, bytes] : one) EXPECT_TRUE(two.at(name) == bytes) << name;
}

// What OPENCV_CPU_DISABLE must say for OpenCV to dispatch as on a CPU whose best ISA is `isa`
// (kept in step with wheelpose_isa_tests in cmake/WheelposeTargets.cmake).
std::string opencv_cap(wheelpose::Isa isa) {
  switch (isa) {
    case wheelpose::Isa::kSse42:
      return "AVX512-SKX,AVX512F,AVX2,FMA3,AVX,FP16";
    case wheelpose::Isa::kAvx:
      return "AVX512-SKX,AVX512F,AVX2,FMA3";
    case wheelpose::Isa::kAvx2:
      return "AVX512-SKX,AVX512F";
    case wheelpose::Isa::kAvx512:
      return "";
  }
  return "";
}

// Embree's SSE4.2 and AVX kernels compute a hit alike (measured); its AVX2 and AVX-512 kernels
// are built with fused multiply-adds and each their own instruction sequence, so a hit's
// distance and barycentrics may differ in the last bit between these three families.
int kernel_family(wheelpose::Isa isa) { return std::max(0, static_cast<int>(isa) - 1); }

// Files whose values may move by one unit between kernel families: colour, depth, normals.
bool follows_hit_distance(const std::string& path) {
  return path.starts_with("images/") || path.ends_with("_depth.png") ||
         path.ends_with("_normals.png");
}

// Run as each ISA this CPU has (Embree's kernels, our AVX2 loops and OpenCV's dispatch all
// capped): within a kernel family every file is the same bytes; across them labels, masks and
// instance/semantic maps are, and images, depth and normals differ by at most one level in a
// few values.
TEST(GenerateCli, SameBytesOnEveryIsa) {
  const auto dir = fresh_temp_dir("generate_isa");
  const fs::path config = write_scenario(dir);
  const std::vector<wheelpose::Isa> isas = wheelpose::isas_on_this_cpu();
  ASSERT_FALSE(isas.empty());
  std::map<int, std::pair<std::string, std::map<std::string, std::string>>> family_first;
  for (wheelpose::Isa isa : isas) {
    const std::string name = wheelpose::isa_name(isa);
    const fs::path out = dir / name;
    const auto r =
        run_wheelpose(generate_args(config, out, 3), "WHEELPOSE_EMBREE_CONFIG=isa=" + name +
                                                         " OPENCV_CPU_DISABLE=" + opencv_cap(isa));
    ASSERT_EQ(r.exit_code, 0) << name << ": " << r.output;
    const auto files = tree(out);
    ASSERT_GT(files.size(), 3u) << name;
    for (const auto& [family, first] : family_first) {
      const bool same_family = family == kernel_family(isa);
      ASSERT_EQ(files.size(), first.second.size()) << name;
      for (const auto& [path, bytes] : first.second) {
        ASSERT_TRUE(files.count(path)) << path << " missing for " << name;
        if (same_family || !follows_hit_distance(path)) {
          EXPECT_TRUE(files.at(path) == bytes)
              << path << " differs between " << first.first << " and " << name;
          continue;
        }
        const cv::Mat a = cv::imread((dir / first.first / path).string(), cv::IMREAD_UNCHANGED);
        const cv::Mat b = cv::imread((out / path).string(), cv::IMREAD_UNCHANGED);
        ASSERT_EQ(a.size(), b.size()) << path;
        cv::Mat diff;
        cv::absdiff(a, b, diff);
        double largest = 0;
        cv::minMaxLoc(diff.reshape(1), nullptr, &largest);
        const double share = static_cast<double>(cv::countNonZero(diff.reshape(1))) /
                             static_cast<double>(diff.total() * diff.channels());
        EXPECT_LE(largest, 1.0) << path << " between " << first.first << " and " << name;
        EXPECT_LE(share, 0.005) << path << " between " << first.first << " and " << name;
      }
    }
    family_first.try_emplace(kernel_family(isa), name, files);
  }
  if (isas.size() < 4) {
    std::cout << "[ NOTE ] this CPU has ISAs up to " << wheelpose::isa_name(isas.back())
              << "; higher ones were not compared\n";
  }
}

// Asking Embree for an ISA the CPU lacks, or for a setting it does not know, is one line and
// exit 2, not a crash or a silently ignored setting.
TEST(GenerateCli, BadEmbreeConfigGivesOneClearLine) {
  const auto dir = fresh_temp_dir("generate_bad_isa");
  const fs::path config = write_scenario(dir);
  auto r = run_wheelpose(generate_args(config, dir / "o", 1), "WHEELPOSE_EMBREE_CONFIG=isa=avx3");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("WHEELPOSE_EMBREE_CONFIG: unknown isa 'avx3'"), std::string::npos)
      << r.output;
  r = run_wheelpose(generate_args(config, dir / "o2", 1), "WHEELPOSE_EMBREE_CONFIG=thread=2");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("'thread=2' is not an Embree setting"), std::string::npos) << r.output;
  if (!wheelpose::cpu_has(wheelpose::Isa::kAvx512)) {
    r = run_wheelpose(generate_args(config, dir / "o3", 1), "WHEELPOSE_EMBREE_CONFIG=isa=avx512");
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("but this CPU does not have it"), std::string::npos) << r.output;
  }
}

TEST(GenerateCli, MergedShardsEqualOneRun) {
  const fs::path dir = fresh_temp_dir("generate_shards");
  const fs::path config = write_scenario(dir);
  ASSERT_EQ(run_wheelpose(generate_args(config, dir / "whole", 5)).exit_code, 0);
  std::string shards;
  for (int i = 0; i < 3; ++i) {
    const fs::path out = dir / ("shard" + std::to_string(i));
    const auto r =
        run_wheelpose(generate_args(config, out, 5, "--shard " + std::to_string(i) + "/3"));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    shards += " " + (out / "annotations.json").string();
    for (const auto& e : fs::directory_iterator(out / "images")) {
      EXPECT_EQ(read_text(e.path()), read_text(dir / "whole" / "images" / e.path().filename()));
    }
  }
  const auto m = run_wheelpose("coco merge" + shards + " --out " + (dir / "merged.json").string());
  ASSERT_EQ(m.exit_code, 0) << m.output;
  EXPECT_TRUE(read_text(dir / "merged.json") == read_text(dir / "whole" / "annotations.json"));
}

TEST(GenerateCli, KilledAndResumedRunsWriteTheSameBytes) {
  const fs::path dir = fresh_temp_dir("generate_resume");
  const fs::path config = write_scenario(dir);
  ASSERT_EQ(run_wheelpose(generate_args(config, dir / "clean", 8)).exit_code, 0);
  // Kill -9 after growing delays until a run completes; each re-run resumes.
  const auto runs = run_killed_until_done(
      [&] { return generate_args(config, dir / "killed", 8, "--resume"); }, 0.3, 0.15);
  ASSERT_EQ(runs.failure, "");
  EXPECT_GE(runs.kills, 2);
  const auto clean = tree(dir / "clean"), killed = tree(dir / "killed");
  EXPECT_EQ(clean.size(), killed.size());
  for (const auto& [name, bytes] : clean)
    EXPECT_TRUE(killed.count(name) && killed.at(name) == bytes) << name;
}

TEST(GenerateCli, ClipsFromARankingRestrictTheMotions) {
  const fs::path dir = fresh_temp_dir("generate_ranking");
  const json ranking = {
      {"format", "wheelpose.review_ranking"},
      {"kept", {{{"id", "library/dance_arm_wave"}}, {{"id", "library/stretch_reach_forward"}}}}};
  std::ofstream(dir / "ranking.json") << ranking.dump();
  const auto r = run_wheelpose(generate_args(write_scenario(dir), dir / "out", 3,
                                             "--clips-from " + (dir / "ranking.json").string()));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json coco = read_json(dir / "out" / "annotations.json");
  ASSERT_FALSE(coco["annotations"].empty());
  for (const json& a : coco["annotations"]) {
    const std::string id = a["motion_id"];
    EXPECT_TRUE(id == "dance_arm_wave" || id == "stretch_reach_forward") << id;
  }
  const json record = read_json(dir / "out" / "scenario.json");
  EXPECT_EQ(record["motions"].size(), 2u);
}

// Every person's MakeHuman assets are in its annotation; exclude_assets keeps the named ones out
// (a training set that never sees some clothes and hair), and a name not installed is an error.
TEST(GenerateCli, ExcludedAssetsAreNeverWorn) {
  const fs::path dir = fresh_temp_dir("generate_assets");
  const std::string excluded =
      "[hair/bob01, hair/short02, clothes/male_casualsuit01, "
      "clothes/female_casualsuit01, clothes/shoes01]";
  std::ofstream(dir / "holdout.yaml")
      << kSmallScenario << "  HumanGeneration: {min_per_frame: 3, max_per_frame: 5, pool_size: 8,"
      << " exclude_assets: " << excluded << "}\n";
  // The base scenario's own HumanGeneration line is replaced, not duplicated.
  std::string text = read_text(dir / "holdout.yaml");
  text.erase(text.find("  HumanGeneration: {min_per_frame: 3, max_per_frame: 5, pool_size: 8}\n"),
             std::string("  HumanGeneration: {min_per_frame: 3, max_per_frame: 5, pool_size: 8}\n")
                 .size());
  std::ofstream(dir / "holdout.yaml") << text;
  auto r = run_wheelpose("generate --config " + (dir / "holdout.yaml").string() + " --out " +
                         (dir / "out").string() + " --frames 4 --seed 7");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json coco = read_json(dir / "out" / "annotations.json");
  ASSERT_FALSE(coco["annotations"].empty());
  int worn = 0;
  for (const json& a : coco["annotations"]) {
    for (const json& asset : a.at("assets")) {
      ++worn;
      EXPECT_EQ(excluded.find(asset.get<std::string>() + ","), std::string::npos) << asset;
      EXPECT_EQ(excluded.find(asset.get<std::string>() + "]"), std::string::npos) << asset;
    }
  }
  EXPECT_GT(worn, 0);

  text.replace(text.find("hair/bob01"), 10, "hair/nope99");
  std::ofstream(dir / "holdout.yaml") << text;
  r = run_wheelpose("generate --config " + (dir / "holdout.yaml").string() + " --out " +
                    (dir / "bad").string() + " --frames 2 --seed 7");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("hair/nope99"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "bad" / "annotations.json"));
}

TEST(GenerateCli, PeopleWithoutWheelchairsStandTallerInTheSameScenes) {
  const fs::path dir = fresh_temp_dir("generate_standing");
  const fs::path seated = write_scenario(dir);
  std::ofstream(dir / "standing.yaml")
      << kSmallScenario
      << "  Wheelchair: {manual_weight: 0, sport_weight: 0, power_weight: 0, none_weight: 1}\n";
  for (const char* name : {"seated", "standing"}) {
    const fs::path config = std::string(name) == "seated" ? seated : dir / "standing.yaml";
    const auto r = run_wheelpose(generate_args(config, dir / name, 4));
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  // Same seed: the same people, clips, placements and cameras; only the chairs are gone and
  // the people stand, so their boxes are taller.
  const json with = read_json(dir / "seated" / "annotations.json");
  const json without = read_json(dir / "standing" / "annotations.json");
  std::map<std::pair<int, int>, double> seated_height;
  for (const json& a : with["annotations"]) {
    EXPECT_NE(a["wheelchair_type"], "none");
    seated_height[{a["image_id"].get<int>(), a["pool_slot"].get<int>()}] =
        a["bbox"][3].get<double>();
  }
  double taller = 0, compared = 0;
  for (const json& a : without["annotations"]) {
    EXPECT_EQ(a["wheelchair_type"], "none");
    EXPECT_NE(a["motion_id"], "rest_standing");  // the clips' upper body on straight legs
    const auto it = seated_height.find({a["image_id"].get<int>(), a["pool_slot"].get<int>()});
    if (it == seated_height.end()) continue;
    ++compared;
    if (a["bbox"][3].get<double>() > it->second) ++taller;
  }
  ASSERT_GE(compared, 5);
  EXPECT_GE(taller / compared, 0.7) << taller << " of " << compared;
}

TEST(GenerateCli, BadInputGivesOneClearLine) {
  const fs::path dir = fresh_temp_dir("generate_errors");
  const fs::path bad = dir / "bad.yaml";
  std::ofstream(bad) << "randomizers:\n  Camera:\n    field_of_veiw: {uniform: [5, 50]}\n";
  auto r = run_wheelpose("generate --config " + bad.string() + " --out " + (dir / "o").string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("bad.yaml:3"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("field_of_veiw"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "o" / "annotations.json"));

  std::ofstream(bad) << "randomizers:\n  Cmaera: {}\n";
  r = run_wheelpose("generate --config " + bad.string() + " --out " + (dir / "o").string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("bad.yaml:2"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("Cmaera"), std::string::npos) << r.output;

  std::ofstream(bad) << "image: {width: 160, height: 120}\nrandomizers:\n  Camera:\n"
                        "    field_of_view: {uniform: [50, 5]}\n";
  r = run_wheelpose("generate --config " + bad.string() + " --out " + (dir / "o").string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("bad.yaml:4"), std::string::npos) << r.output;

  r = run_wheelpose("generate --out " + (dir / "o").string() + " --shard 3/2");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("--shard"), std::string::npos) << r.output;

  r = run_wheelpose("generate --out " + (dir / "o").string() + " --motions " +
                    (dir / "missing").string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("missing"), std::string::npos) << r.output;
}

TEST(GenerateCli, StatsRunOnAGeneratedDataset) {
  const fs::path dir = fresh_temp_dir("generate_stats");
  ASSERT_EQ(run_wheelpose(generate_args(write_scenario(dir), dir / "out", 4)).exit_code, 0);
  const auto r = run_wheelpose("stats " + (dir / "out" / "annotations.json").string() +
                               " --reference " + std::string(WHEELPOSE_SHARED_DIR) +
                               "/data/coco-sample/person_keypoints_sample.json --out " +
                               (dir / "stats").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // Our camera metadata feeds the camera analysis the COCO reference lacks.
  const json stats = read_json(dir / "stats" / "stats.json");
  EXPECT_TRUE(stats.dump().find("\"available\":true") != std::string::npos) << stats.dump();
}

}  // namespace

namespace {

// deploy/slurm-generate.sh against a stand-in `sbatch` that runs each array task and then the
// merge job in order: the merged dataset must equal a single run.
TEST(GenerateDeploy, SlurmArrayScriptRendersShardsAndMerges) {
  const fs::path dir = fresh_temp_dir("generate_slurm");
  const fs::path config = write_scenario(dir);
  const fs::path bin = dir / "bin";
  fs::create_directories(bin);
  std::ofstream(bin / "sbatch") << R"(#!/usr/bin/env bash
# Stand-in for Slurm's sbatch: runs the job now (array tasks one after another).
array=""; wrap=""
for arg in "$@"; do
  case "$arg" in
    --array=*) array="${arg#--array=}" ;;
    --wrap=*) wrap="${arg#--wrap=}" ;;
  esac
done
if [ -n "$array" ]; then
  for i in $(seq "${array%-*}" "${array#*-}"); do SLURM_ARRAY_TASK_ID=$i bash -c "$wrap" >/dev/null 2>&1 || exit 1; done
else
  bash -c "$wrap" >/dev/null 2>&1 || exit 1
fi
echo 4242
)";
  fs::permissions(bin / "sbatch", fs::perms::owner_all);
  const std::string command =
      "PATH=" + bin.string() + ":$PATH FRAMES=5 SHARDS=2 SEED=7 OUT=" + (dir / "run").string() +
      " CONFIG=" + config.string() + " WHEELPOSE=" + WHEELPOSE_BINARY + " bash " +
      WHEELPOSE_SOURCE_DIR + "/deploy/slurm-generate.sh > /dev/null 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0);
  const auto single = run_wheelpose("generate --config " + config.string() + " --out " +
                                    (dir / "single").string() + " --frames 5 --seed 7");
  ASSERT_EQ(single.exit_code, 0) << single.output;
  EXPECT_TRUE(read_text(dir / "run" / "dataset" / "annotations.json") ==
              read_text(dir / "single" / "annotations.json"));
  for (const auto& e : fs::directory_iterator(dir / "single" / "images")) {
    EXPECT_TRUE(read_text(e.path()) ==
                read_text(dir / "run" / "dataset" / "images" / e.path().filename()))
        << e.path().filename();
  }
}

}  // namespace

namespace {

// The raised-hips template moves only the hips, 9 cm (times the person's scale) up the torso;
// the as-annotated one also the shoulders, 4 cm, and the ears to the ear's centre (0.5-2.5 cm).
TEST(GenerateCli, AnnotatedTemplatesMoveOnlyTheirPoints) {
  const fs::path dir = fresh_temp_dir("generate_raised_hips");
  const fs::path config = write_scenario(dir);
  ASSERT_EQ(run_wheelpose(generate_args(config, dir / "plain", 2)).exit_code, 0);
  const json a = read_json(dir / "plain" / "annotations.json");
  ASSERT_FALSE(a["annotations"].empty());
  for (const std::string name : {"coco17-raised-hips", "coco17-as-annotated"}) {
    std::string scenario = kSmallScenario;
    scenario.replace(scenario.find("labels: {"), 9, "labels: {keypoint_template: " + name + ", ");
    std::ofstream(dir / (name + ".yaml")) << scenario;
    const auto r = run_wheelpose(generate_args(dir / (name + ".yaml"), dir / name, 2));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const json b = read_json(dir / name / "annotations.json");
    ASSERT_EQ(a["annotations"].size(), b["annotations"].size());
    const bool annotated = name == "coco17-as-annotated";
    for (std::size_t i = 0; i < a["annotations"].size(); ++i) {
      const auto p = a["annotations"][i]["keypoints_3d"].get<std::vector<double>>();
      const auto q = b["annotations"][i]["keypoints_3d"].get<std::vector<double>>();
      const double scale = a["annotations"][i]["scale"];
      for (int k = 0; k < 17; ++k) {
        if (p[3 * k + 2] == 0) continue;  // beyond a limb cut
        const double d = std::hypot(p[3 * k] - q[3 * k], p[3 * k + 1] - q[3 * k + 1],
                                    p[3 * k + 2] - q[3 * k + 2]);
        if (k == 11 || k == 12) {
          EXPECT_NEAR(d, 0.09 * scale, 0.002 * scale) << name << " keypoint " << k;
        } else if (annotated && (k == 5 || k == 6)) {
          EXPECT_NEAR(d, 0.04 * scale, 0.002 * scale) << name << " keypoint " << k;
        } else if (annotated && (k == 3 || k == 4)) {
          EXPECT_GT(d, 0.005 * scale) << name << " keypoint " << k;
          EXPECT_LT(d, 0.025 * scale) << name << " keypoint " << k;
        } else {
          EXPECT_LT(d, 1e-9) << name << " keypoint " << k;
        }
      }
    }
  }
}

TEST(GenerateCli, SetWritesOneKeyOverTheScenario) {
  const fs::path dir = fresh_temp_dir("generate_set");
  const fs::path config = write_scenario(dir);
  std::string scenario = kSmallScenario;
  scenario.replace(scenario.find("labels: {"), 9, "labels: {box: person_and_wheelchair, ");
  std::ofstream(dir / "chair-boxes.yaml") << scenario;
  const auto edited = run_wheelpose(generate_args(dir / "chair-boxes.yaml", dir / "edited", 2));
  ASSERT_EQ(edited.exit_code, 0) << edited.output;
  const auto set = run_wheelpose(
      generate_args(config, dir / "set", 2, "--set labels.box=person_and_wheelchair"));
  ASSERT_EQ(set.exit_code, 0) << set.output;
  // The same frames and labels as the edited file; the resolved scenario records the key.
  EXPECT_EQ(read_text(dir / "set" / "annotations.json"),
            read_text(dir / "edited" / "annotations.json"));
  EXPECT_EQ(tree(dir / "set" / "images"), tree(dir / "edited" / "images"));
  EXPECT_EQ(read_json(dir / "set" / "scenario.json")["scenario"]["labels"]["box"],
            "person_and_wheelchair");

  const struct {
    std::string set, says;
  } cases[] = {
      {"labels.box", "--set 'labels.box': expected KEY=VALUE"},
      {"labels.bogus=1", "key 'labels.bogus': unknown key"},
      {"image.width.x=1", "'image.width' is not a map of keys"},
      {"labels.box=[a", "the value is not YAML"},
  };
  for (const auto& c : cases) {
    const auto r = run_wheelpose(generate_args(config, dir / "bad", 1, "--set " + c.set));
    EXPECT_EQ(r.exit_code, 2) << c.set << "\n" << r.output;
    EXPECT_NE(r.output.find(c.says), std::string::npos) << c.set << "\n" << r.output;
    EXPECT_EQ(r.output.find('\n'), r.output.size() - 1) << "one line: " << r.output;
    EXPECT_FALSE(fs::exists(dir / "bad")) << c.set;
  }
}

}  // namespace
