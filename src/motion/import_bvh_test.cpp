#include "motion/import_bvh.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "motion/import_test_util.h"

namespace wheelpose::motion {
namespace {

using ::testing::HasSubstr;
using testing::ScratchDir;

const std::string kShared = WHEELPOSE_SHARED_DIR;

// Root with 6 channels, one child rotating about Z then X, and an end site.
constexpr const char* kTinyHierarchy = R"(HIERARCHY
ROOT Hips
{
  OFFSET 0 0 0
  CHANNELS 6 Xposition Yposition Zposition Zrotation Yrotation Xrotation
  JOINT Arm
  {
    OFFSET 0 1 0
    CHANNELS 2 Zrotation Xrotation
    End Site
    {
      OFFSET 0 0 2
    }
  }
}
)";

std::string error_of(const std::string& text) {
  try {
    parse_bvh(text, "t.bvh");
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(ParseBvh, ReadsHierarchyChannelsAndFrames) {
  BvhMotion m = parse_bvh(std::string(kTinyHierarchy) +
                              "MOTION\nFrames: 2\nFrame Time: .04\n"
                              "1 2 3 0 0 0 0 0\n1 2 3 90 0 90 0 +90\n",
                          "t.bvh");
  ASSERT_EQ(m.joints.size(), 3u);
  EXPECT_EQ(m.joints[1].name, "Arm");
  EXPECT_EQ(m.joints[1].parent, 0);
  EXPECT_EQ(m.joints[1].first_channel, 6);
  EXPECT_EQ(m.joints[2].name, "Arm.end");
  EXPECT_TRUE(m.joints[2].end_site);
  EXPECT_EQ(m.channel_count, 8);
  EXPECT_DOUBLE_EQ(m.frame_time, 0.04);
  ASSERT_EQ(m.frames.size(), 2u);
  EXPECT_EQ(m.frames[1][7], 90.0);
}

TEST(ImportBvh, RoundedFrameTimesMeanTheNearbyStandardRate) {
  EXPECT_EQ(bvh_frame_rate(.0083333), 120.0);
  EXPECT_EQ(bvh_frame_rate(0.033333), 30.0);
  EXPECT_EQ(bvh_frame_rate(.04), 25.0);
  EXPECT_EQ(bvh_frame_rate(0.0333667), 30000.0 / 1001.0);
  EXPECT_EQ(bvh_frame_rate(0.5), 2.0);
  // Not near a standard rate: kept as given.
  EXPECT_DOUBLE_EQ(bvh_frame_rate(0.0123), 1 / 0.0123);
  EXPECT_DOUBLE_EQ(bvh_frame_rate(0.0334), 1 / 0.0334);
}

TEST(ParseBvh, ForwardKinematicsComposesChannelsInListedOrder) {
  BvhMotion m = parse_bvh(std::string(kTinyHierarchy) +
                              "MOTION\nFrames: 2\nFrame Time: .04\n"
                              "1 2 3 0 0 0 0 0\n1 2 3 90 0 90 0 90\n",
                          "t.bvh");
  auto rest = bvh_global_positions(m, 0);
  EXPECT_TRUE(rest[0].isApprox(Eigen::Vector3d(1, 2, 3)));
  EXPECT_TRUE(rest[1].isApprox(Eigen::Vector3d(1, 3, 3)));
  EXPECT_TRUE(rest[2].isApprox(Eigen::Vector3d(1, 3, 5)));
  // Root R = Rz(90) Rx(90): the child offset (0,1,0) -> Rx -> (0,0,1) -> Rz -> (0,0,1).
  // (The reverse order would give (-1,0,0).)
  auto posed = bvh_global_positions(m, 1);
  EXPECT_TRUE(posed[1].isApprox(Eigen::Vector3d(1, 2, 4))) << posed[1].transpose();
  // Arm's global rotation = Rz(90) Rx(90) Rx(90) = Rz(90) Rx(180): (0,0,2) -> (0,0,-2).
  EXPECT_TRUE(posed[2].isApprox(Eigen::Vector3d(1, 2, 2))) << posed[2].transpose();
}

TEST(ParseBvh, ReportsMalformedFilesWithLineNumbers) {
  const std::string head = std::string(kTinyHierarchy) + "MOTION\nFrames: 2\nFrame Time: .04\n";
  // kTinyHierarchy has 15 lines; MOTION is line 16, the frame lines 19 and 20.
  EXPECT_THAT(error_of(head + "1 2 3 0 0 0 0 0\n"),
              HasSubstr("truncated MOTION section: 'Frames: 2' but only 1 frame lines"));
  EXPECT_THAT(error_of(head + "1 2 3 0 0 0 0 0\n1 2 3 0 0 0 0\n"),
              HasSubstr("t.bvh:20: 7 values on a frame line, expected 8"));
  EXPECT_THAT(
      error_of(head + "1 2 3 0 0 0 0 0\n1 2 abc 0 0 0 0 0\n"),
      HasSubstr("t.bvh:20: 'abc' is not a number (frame 1, joint Hips, channel Zposition)"));
  EXPECT_THAT(
      error_of(head + "1 2 3 0 0 0 0 0\n1 2 nan 0 0 0 0 0\n"),
      HasSubstr("t.bvh:20: 'nan' is not a finite number (frame 1, joint Hips, channel Zposition)"));
  EXPECT_THAT(error_of(head + "1 2 3 0 0 0 0 0\n1 2 3 0 0 0 0 0\n1 2 3 0 0 0 0 0\n"),
              HasSubstr("t.bvh:21: more frame lines than 'Frames: 2'"));
  EXPECT_THAT(error_of(std::string(kTinyHierarchy)), HasSubstr("no MOTION section"));
  EXPECT_THAT(error_of(std::string(kTinyHierarchy).substr(0, 120)),
              HasSubstr("unexpected end of hierarchy"));
  std::string bad_channel = kTinyHierarchy;
  bad_channel.replace(bad_channel.find("Zrotation Xrotation"), 9, "Wrotation");
  EXPECT_THAT(error_of(bad_channel + "MOTION\nFrames: 1\nFrame Time: 1\n"),
              HasSubstr("t.bvh:9: unknown channel 'Wrotation'"));
  EXPECT_THAT(error_of("ROOT x"), HasSubstr("does not start with HIERARCHY"));
  EXPECT_THAT(error_of(std::string(kTinyHierarchy) + "MOTION\nFrames: 1\nFrame Time: 0\n"),
              HasSubstr("Frame Time must be positive"));
}

TEST(ImportBvh, CmuFilesGivePlausibleBodiesInMetres) {
  // Every BVH file in the shared data; the frame count is read from its "Frames:" line.
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(kShared + "/data/bvh")) {
    if (entry.path().extension() != ".bvh") continue;
    ++files;
    const std::string path = entry.path().string();
    const std::string stem = entry.path().stem().string();
    const std::string text = read_file(path);
    const std::size_t frames = std::stoul(text.substr(text.find("Frames:") + 7));
    PositionClip clip = import_bvh(path, {});
    SCOPED_TRACE(path);
    EXPECT_EQ(clip.name, stem);
    EXPECT_EQ(clip.source, path);
    ASSERT_EQ(clip.frames.size(), frames);
    EXPECT_EQ(clip.fps, 120.0);  // Frame Time .0083333
    for (std::size_t f = 0; f < clip.frames.size(); ++f) {
      const Pose& p = clip.frames[f];
      ASSERT_GT(p[kHeadTop].y(), p[kPelvis].y()) << "frame " << f;
      ASSERT_GT(p[kHeadBase].y(), p[kUpperChest].y()) << "frame " << f;
      // Rigid bones: thigh 7.29 units, shin 6.92 units in the file.
      ASSERT_NEAR((p[kLeftKnee] - p[kLeftHip]).norm(), 0.411, 0.002) << "frame " << f;
      ASSERT_NEAR((p[kLeftAnkle] - p[kLeftKnee]).norm(), 0.390, 0.002) << "frame " << f;
      ASSERT_NEAR((p[kRightElbow] - p[kRightShoulder]).norm(), 4.46073 * 0.0254 / 0.45, 1e-6);
      ASSERT_NEAR(p[kNeckBase].x(), (p[kLeftClavicle].x() + p[kRightClavicle].x()) / 2, 1e-9);
    }
    // Pelvis to top of head: this conversion of the CMU skeleton has no thorax bone, so the
    // trunk + head chain is only 8.82 units = 0.498 m long (legs are adult-sized, see above).
    double reach = (clip.frames[0][kHeadTop] - clip.frames[0][kPelvis]).norm();
    EXPECT_GT(reach, 0.45);
    EXPECT_LT(reach, 0.50);
  }
  EXPECT_GE(files, 3);
}

// The cmu_mb (MotionBuilder names) rig on a zero-rotation file: positions = summed offsets.
TEST(ImportBvh, MotionBuilderNamedRigIsChosenWhenCmuNamesAreAbsent) {
  std::ostringstream s;
  s << "HIERARCHY\nROOT Hips\n{\nOFFSET 0 0 0\nCHANNELS 3 Xposition Yposition Zposition\n";
  // name, offset; nested chains as (name, offset) lists closed together.
  auto chain = [&](const std::vector<std::pair<std::string, std::string>>& joints, bool end) {
    for (const auto& [name, offset] : joints) {
      s << "JOINT " << name << "\n{\nOFFSET " << offset << "\nCHANNELS 1 Zrotation\n";
    }
    if (end) s << "End Site\n{\nOFFSET 0 2 0\n}\n";
    for (std::size_t i = 0; i < joints.size(); ++i) s << "}\n";
  };
  chain({{"LeftUpLeg", "1 -1 0"},
         {"LeftLeg", "0 -7 0"},
         {"LeftFoot", "0 -7 0"},
         {"LeftToeBase", "0 -1 2"}},
        false);
  chain({{"RightUpLeg", "-1 -1 0"},
         {"RightLeg", "0 -7 0"},
         {"RightFoot", "0 -7 0"},
         {"RightToeBase", "0 -1 2"}},
        false);
  s << "JOINT Spine\n{\nOFFSET 0 2 0\nCHANNELS 1 Zrotation\nJOINT Spine1\n{\nOFFSET 0 2 0\n"
       "CHANNELS 1 Zrotation\n";
  chain({{"Neck1", "0 2 0"}, {"Head", "0 2 0"}}, true);
  chain({{"LeftShoulder", "0 0 0"},
         {"LeftArm", "3 1 0"},
         {"LeftForeArm", "4 0 0"},
         {"LeftHand", "3 0 0"}},
        false);
  chain({{"RightShoulder", "0 0 0"},
         {"RightArm", "-3 1 0"},
         {"RightForeArm", "-4 0 0"},
         {"RightHand", "-3 0 0"}},
        false);
  s << "}\n}\n}\nMOTION\nFrames: 1\nFrame Time: 0.5\n0 10 0";
  for (int i = 0; i < 20; ++i) s << " 0";
  s << "\n";
  ScratchDir dir;
  auto path = dir.write("mb.bvh", s.str());
  ImportOptions options;
  options.unit_scale = 0.1;
  PositionClip clip = import_bvh(path, options);
  EXPECT_EQ(clip.fps, 2.0);
  const Pose& p = clip.frames[0];
  EXPECT_TRUE(p[kPelvis].isApprox(Eigen::Vector3d(0, 1.0, 0)));
  EXPECT_TRUE(p[kLeftHip].isApprox(Eigen::Vector3d(0.1, 0.9, 0)));
  EXPECT_TRUE(p[kLeftToe].isApprox(Eigen::Vector3d(0.1, -0.6, 0.2)));
  EXPECT_TRUE(p[kChest].isApprox(Eigen::Vector3d(0, 1.3, 0)));
  EXPECT_TRUE(p[kHeadBase].isApprox(Eigen::Vector3d(0, 1.6, 0)));
  EXPECT_TRUE(p[kHeadTop].isApprox(Eigen::Vector3d(0, 2.0, 0)));  // Head's end site
  EXPECT_TRUE(p[kLeftClavicle].isApprox(Eigen::Vector3d(0.15, 1.45, 0)));
  EXPECT_TRUE(p[kNeckBase].isApprox(Eigen::Vector3d(0, 1.45, 0)));
  EXPECT_TRUE(p[kRightWrist].isApprox(Eigen::Vector3d(-1.0, 1.5, 0)));

  // Naming the other rig fails, naming the missing joint.
  options.mapping = "cmu";
  try {
    import_bvh(path, options);
    ADD_FAILURE() << "cmu rig accepted MotionBuilder names";
  } catch (const Error& e) {
    EXPECT_THAT(e.what(),
                HasSubstr("joint 'LeftHip' (needed for left_hip by mapping 'cmu') is missing"));
  }
}

TEST(ImportBvh, RejectsUnknownJointsAndMappings) {
  ScratchDir dir;
  std::string text = read_file(kShared + "/data/bvh/131_01.bvh");
  std::string renamed = text;
  renamed.replace(renamed.find("JOINT LeftKnee"), 14, "JOINT LKnee");
  auto path = dir.write("renamed.bvh", renamed);
  try {
    import_bvh(path, {});
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_THAT(e.what(), HasSubstr(path.string()));
    EXPECT_THAT(e.what(), HasSubstr("joint 'LeftKnee'"));
  }
  ImportOptions options;
  options.mapping = "vicon";
  try {
    import_bvh(kShared + "/data/bvh/131_01.bvh", options);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_THAT(e.what(), HasSubstr("unknown BVH mapping 'vicon' (built in: cmu, cmu_mb)"));
  }
  // A frame line cut short, as in a truncated download.
  auto cut = dir.write("cut.bvh", text.substr(0, text.size() / 2));
  EXPECT_THROW(import_bvh(cut, {}), Error);
}

}  // namespace
}  // namespace wheelpose::motion
