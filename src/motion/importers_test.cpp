#include "motion/importers.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "core/atomic_file.h"
#include "core/error.h"
#include "motion/import_test_util.h"

namespace wheelpose::motion {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;
using testing::npy_bytes;
using testing::ScratchDir;

const std::string kBvh = std::string(WHEELPOSE_SHARED_DIR) + "/data/bvh/131_02.bvh";

std::string error_of(const std::filesystem::path& path, const ImportOptions& options) {
  try {
    import_motion(path, options);
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::kBadInput);
    return e.what();
  }
  return "no error";
}

std::string one_frame_json() {
  std::string s = "{\"joints\": [";
  for (int j = 0; j < kJointCount; ++j)
    s += std::string(j ? "," : "") + "\"" + std::string(joint_name(j)) + "\"";
  s += "], \"frames\": [[";
  for (int j = 0; j < kJointCount; ++j)
    s += std::string(j ? "," : "") + "[" + std::to_string(j) + ",1,2]";
  return s + "]]}";
}

TEST(Importers, ListsTheFormats) {
  EXPECT_THAT(importer_formats(), ElementsAre("npy", "bvh", "csv", "json"));
}

TEST(Importers, ChoosesTheImporterByExtension) {
  ScratchDir dir;
  std::vector<double> values(2 * 22 * 3, 0.25);
  PositionClip npy = import_motion(dir.write("gen.NPY", npy_bytes("<f4", {2, 22, 3}, values)), {});
  EXPECT_EQ(npy.name, "gen");
  EXPECT_EQ(npy.fps, 20.0);
  EXPECT_EQ(npy.frames.size(), 2u);

  PositionClip bvh = import_motion(kBvh, {});
  EXPECT_EQ(bvh.name, "131_02");
  EXPECT_EQ(bvh.source, kBvh);
  EXPECT_EQ(bvh.frames.size(), 1247u);

  PositionClip json = import_motion(dir.write("kp.json", one_frame_json()), {});
  EXPECT_EQ(json.frames[0][kRightWrist], Eigen::Vector3d(kRightWrist, 1, 2));

  std::string csv_text = "# fps: 60\nframe,joint,x,y,z\n";
  for (int j = 0; j < kJointCount; ++j) {
    csv_text += "7," + std::string(joint_name(j)) + "," + std::to_string(j) + ",0,0\n";
  }
  PositionClip csv = import_motion(dir.write("kp.Csv", csv_text), {});
  EXPECT_EQ(csv.fps, 60.0);
  ASSERT_EQ(csv.frames.size(), 1u);
  EXPECT_EQ(csv.frames[0][kLeftElbow], Eigen::Vector3d(kLeftElbow, 0, 0));
}

TEST(Importers, NamedFormatOverridesTheExtension) {
  ScratchDir dir;
  auto path = dir.write("keypoints.txt", one_frame_json());
  ImportOptions options;
  options.format = "json";
  options.fps = 12;
  PositionClip clip = import_motion(path, options);
  EXPECT_EQ(clip.name, "keypoints");
  EXPECT_EQ(clip.source, path.string());
  EXPECT_EQ(clip.fps, 12.0);
  // The same bytes read as BVH fail in the BVH parser, naming the file.
  options.format = "bvh";
  EXPECT_THAT(error_of(path, options),
              HasSubstr(path.string() + ":1: file does not start with HIERARCHY"));
}

TEST(Importers, RejectsUnknownFormatsAndBadOptions) {
  ScratchDir dir;
  auto path = dir.write("motion.fbx", "x");
  EXPECT_THAT(error_of(path, {}),
              HasSubstr("cannot tell the motion format from the extension '.fbx' (formats: npy, "
                        "bvh, csv, json; name one explicitly)"));
  ImportOptions options;
  options.format = "c3d";
  EXPECT_THAT(error_of(path, options),
              HasSubstr("unknown motion format 'c3d' (formats: npy, bvh, csv, json)"));
  options = {};
  options.fps = -1;
  EXPECT_THAT(error_of(kBvh, options), HasSubstr("fps must not be negative"));
  EXPECT_THAT(error_of(dir.path() / "missing.bvh", {}), HasSubstr("missing.bvh"));
}

}  // namespace
}  // namespace wheelpose::motion
