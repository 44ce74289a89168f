#include "motion/import_keypoints.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <sstream>

#include "core/error.h"
#include "motion/import_test_util.h"

namespace wheelpose::motion {
namespace {

using ::testing::HasSubstr;
using testing::ScratchDir;

// Joint j of frame t at (j, t, 0.5 j).
Eigen::Vector3d point(int j, int t) { return {double(j), double(t), 0.5 * j}; }

std::string long_csv(int frames, bool with_neck_base) {
  std::ostringstream s;
  s << "# fps: 50\nframe,joint,x,y,z\n";
  for (int t = 0; t < frames; ++t) {
    // Joints in reverse order: the importer goes by name.
    for (int j = kJointCount - 1; j >= 0; --j) {
      if (j == kNeckBase && !with_neck_base) continue;
      auto p = point(j, t);
      s << t << "," << joint_name(j) << "," << p.x() << "," << p.y() << "," << p.z() << "\n";
    }
  }
  return s.str();
}

std::string wide_csv(int frames) {
  std::ostringstream s;
  s << "frame";
  for (int j = 0; j < kJointCount; ++j) {
    s << "," << joint_name(j) << "_x," << joint_name(j) << "_y," << joint_name(j) << "_z";
  }
  s << "\n";
  for (int t = 0; t < frames; ++t) {
    s << t + 1;
    for (int j = 0; j < kJointCount; ++j) {
      auto p = point(j, t);
      s << "," << p.x() << "," << p.y() << "," << p.z();
    }
    s << "\n";
  }
  return s.str();
}

std::string error_csv(const ScratchDir& dir, const std::string& text,
                      const std::string& mapping = "") {
  auto path = dir.write("bad.csv", text);
  ImportOptions options;
  options.mapping = mapping;
  try {
    import_keypoints_csv(path, options);
  } catch (const Error& e) {
    std::string what = e.what();
    EXPECT_THAT(what, HasSubstr(path.string()));
    return what.substr(path.string().size());
  }
  return "no error";
}

std::string error_json(const ScratchDir& dir, const std::string& text) {
  auto path = dir.write("bad.json", text);
  try {
    import_keypoints_json(path, {});
  } catch (const Error& e) {
    std::string what = e.what();
    EXPECT_THAT(what, HasSubstr(path.string()));
    return what.substr(path.string().size());
  }
  return "no error";
}

TEST(ImportKeypoints, Wheelpose23LongCsvDerivesTheNeckBase) {
  ScratchDir dir;
  PositionClip clip = import_keypoints_csv(dir.write("seq.csv", long_csv(3, false)), {});
  EXPECT_EQ(clip.name, "seq");
  EXPECT_EQ(clip.fps, 50.0);
  ASSERT_EQ(clip.frames.size(), 3u);
  for (int j = 0; j < kJointCount; ++j) {
    if (j == kNeckBase) continue;
    EXPECT_EQ(clip.frames[2][j], point(j, 2)) << joint_name(j);
  }
  EXPECT_EQ(clip.frames[2][kNeckBase], (point(kLeftClavicle, 2) + point(kRightClavicle, 2)) / 2);
}

TEST(ImportKeypoints, LongAndWideCsvAndJsonAgree) {
  ScratchDir dir;
  PositionClip a = import_keypoints_csv(dir.write("a.csv", long_csv(4, true)), {});
  PositionClip b = import_keypoints_csv(dir.write("b.csv", "\xEF\xBB\xBF" + wide_csv(4)), {});
  std::ostringstream json;
  json << "{\"joints\": [";
  for (int j = 0; j < kJointCount; ++j) json << (j ? "," : "") << '"' << joint_name(j) << '"';
  json << "], \"frames\": [";
  for (int t = 0; t < 4; ++t) {
    json << (t ? "," : "") << "[";
    for (int j = 0; j < kJointCount; ++j) {
      auto p = point(j, t);
      json << (j ? "," : "") << "[" << p.x() << "," << p.y() << "," << p.z() << "]";
    }
    json << "]";
  }
  json << "]}";
  PositionClip c = import_keypoints_json(dir.write("c.json", json.str()), {});
  EXPECT_EQ(b.fps, 30.0);  // neither file states a rate
  EXPECT_EQ(c.fps, 30.0);
  ASSERT_EQ(a.frames.size(), 4u);
  ASSERT_EQ(b.frames.size(), 4u);
  ASSERT_EQ(c.frames.size(), 4u);
  for (int t = 0; t < 4; ++t) {
    for (int j = 0; j < kJointCount; ++j) {
      EXPECT_EQ(a.frames[t][j], point(j, t));
      EXPECT_EQ(b.frames[t][j], point(j, t));
      EXPECT_EQ(c.frames[t][j], point(j, t));
    }
  }
  ImportOptions options;
  options.fps = 24;
  options.unit_scale = 0.001;  // millimetres
  PositionClip mm = import_keypoints_csv(dir.path() / "b.csv", options);
  EXPECT_EQ(mm.fps, 24.0);
  EXPECT_TRUE(mm.frames[1][kHeadTop].isApprox(point(kHeadTop, 1) * 0.001));
}

TEST(ImportKeypoints, BlazePoseWorldLandmarksBecomeYUpJoints) {
  // A subject facing the camera, MediaPipe frame (x image-right, y down, z away from camera):
  // hips at y = 0, shoulders 0.5 m up (y = -0.5), ears 0.7 m up, feet pointing at the camera.
  std::map<std::string, Eigen::Vector3d> lm = {{"left_hip", {0.1, 0, 0}},
                                               {"right_hip", {-0.1, 0, 0}},
                                               {"left_shoulder", {0.2, -0.5, 0}},
                                               {"right_shoulder", {-0.2, -0.5, 0}},
                                               {"left_ear", {0.08, -0.7, 0}},
                                               {"right_ear", {-0.08, -0.7, 0}},
                                               {"left_elbow", {0.45, -0.5, 0}},
                                               {"right_elbow", {-0.45, -0.5, 0}},
                                               {"left_wrist", {0.7, -0.5, 0}},
                                               {"right_wrist", {-0.7, -0.5, 0}},
                                               {"left_knee", {0.1, 0.4, 0}},
                                               {"right_knee", {-0.1, 0.4, 0}},
                                               {"left_ankle", {0.1, 0.8, 0}},
                                               {"right_ankle", {-0.1, 0.8, 0}},
                                               {"left_foot_index", {0.1, 0.85, -0.15}},
                                               {"right_foot_index", {-0.1, 0.85, -0.15}},
                                               {"nose", {0, -0.68, -0.1}}};
  std::ostringstream s;
  s << "{\"fps\": 15, \"joints\": [";
  bool first = true;
  for (const auto& [name, p] : lm) {
    s << (first ? "" : ",") << '"' << name << '"';
    first = false;
  }
  s << "], \"frames\": [[";
  first = true;
  for (const auto& [name, p] : lm) {
    s << (first ? "" : ",") << "[" << p.x() << "," << p.y() << "," << p.z() << "]";
    first = false;
  }
  s << "]]}";
  ScratchDir dir;
  ImportOptions options;
  options.mapping = "blazepose33";
  PositionClip clip = import_keypoints_json(dir.write("mp.json", s.str()), options);
  EXPECT_EQ(clip.fps, 15.0);
  const Pose& p = clip.frames[0];
  using V = Eigen::Vector3d;
  EXPECT_TRUE(p[kPelvis].isApprox(V(0, 0, 0)));
  EXPECT_TRUE(p[kLeftHip].isApprox(V(0.1, 0, 0)));  // subject's left at +X
  EXPECT_TRUE(p[kLeftAnkle].isApprox(V(0.1, -0.8, 0)));
  EXPECT_TRUE(p[kLeftToe].isApprox(V(0.1, -0.85, 0.15)));  // feet point forward, +Z
  EXPECT_TRUE(p[kSpine].isApprox(V(0, 0.125, 0)));
  EXPECT_TRUE(p[kChest].isApprox(V(0, 0.25, 0)));
  EXPECT_TRUE(p[kUpperChest].isApprox(V(0, 0.375, 0)));
  EXPECT_TRUE(p[kNeckBase].isApprox(V(0, 0.5, 0)));
  EXPECT_TRUE(p[kLeftClavicle].isApprox(V(0.04, 0.5, 0)));
  EXPECT_TRUE(p[kRightClavicle].isApprox(V(-0.04, 0.5, 0)));
  EXPECT_TRUE(p[kHeadBase].isApprox(V(0, 0.6, 0)));
  EXPECT_TRUE(p[kHeadTop].isApprox(V(0, 0.8, 0)));
  EXPECT_TRUE(p[kRightWrist].isApprox(V(-0.7, 0.5, 0)));
}

TEST(ImportKeypoints, ReportsBadCsvWithLineNumbers) {
  ScratchDir dir;
  const std::string head = "frame,joint,x,y,z\n";
  EXPECT_EQ(error_csv(dir, head + "0,left_kneee,1,2,3\n"),
            ":2: unknown joint 'left_kneee' for mapping 'wheelpose23'");
  EXPECT_EQ(error_csv(dir, head + "0,pelvis,1,2\n"),
            ":2: 4 values, expected 5 (as in the header on line 1)");
  EXPECT_EQ(error_csv(dir, head + "0,pelvis,1,2,3\n0,left_hip,1,NaN,3\n"),
            ":3: 'NaN' is not a finite number (frame 0, joint left_hip)");
  EXPECT_EQ(error_csv(dir, head + "0,pelvis,1,2,x3\n"),
            ":2: 'x3' is not a number (frame 0, joint pelvis)");
  EXPECT_EQ(error_csv(dir, head + "0,pelvis,1,2,3\n0,pelvis,1,2,3\n"),
            ":3: joint 'pelvis' appears twice in frame 0 (first on line 2)");
  EXPECT_EQ(error_csv(dir, head + "a,pelvis,1,2,3\n"),
            ":2: frame 'a' is not a non-negative integer");
  EXPECT_EQ(error_csv(dir, head), ": no frames");
  EXPECT_EQ(error_csv(dir, ""), ": empty CSV file (no header)");
  EXPECT_EQ(error_csv(dir, "frame,x,y\n"),
            ":1: header must be 'frame,joint,x,y,z' or 'frame,<joint>_x,<joint>_y,<joint>_z,...'");
  EXPECT_EQ(error_csv(dir, "frame,pelvis_x,pelvis_z,pelvis_y\n"),
            ":1: columns after 'pelvis_x' should be 'pelvis_y,pelvis_z'");
  EXPECT_EQ(error_csv(dir, "frame,nose_x,nose_y,nose_z\n"),
            ":1: unknown joint 'nose' for mapping 'wheelpose23'");
  // Missing joints and frame gaps.
  std::string full = long_csv(3, true);
  std::string no_knee;
  std::istringstream lines(full);
  for (std::string line; std::getline(lines, line);) {
    if (line.find(",left_knee,") == std::string::npos) no_knee += line + "\n";
  }
  EXPECT_EQ(error_csv(dir, no_knee),
            ": joint 'left_knee' (needed for left_knee by mapping 'wheelpose23') is missing");
  std::string gap;
  std::istringstream lines2(full);
  for (std::string line; std::getline(lines2, line);) {
    if (line.rfind("1,", 0) != 0) gap += line + "\n";
  }
  EXPECT_EQ(error_csv(dir, gap), ": frame 1 has no rows (frames must be consecutive)");
  std::string one_missing = full;
  one_missing.erase(one_missing.find("2,left_wrist"),
                    one_missing.find('\n', one_missing.find("2,left_wrist")) -
                        one_missing.find("2,left_wrist") + 1);
  EXPECT_EQ(error_csv(dir, one_missing),
            ": frame 2 has no row for joint 'left_wrist' (other frames have one)");
  std::string wide = wide_csv(3);
  std::string skipped = wide.substr(0, wide.find("\n2,") + 1) + wide.substr(wide.find("\n3,") + 1);
  EXPECT_EQ(error_csv(dir, skipped), ":3: frame 3 follows frame 1 (frames must be consecutive)");
  EXPECT_EQ(error_csv(dir, "# fps: -3\n" + head), ":1: fps must be positive");
  EXPECT_THAT(
      error_csv(dir, long_csv(1, true), "openpose"),
      HasSubstr("unknown keypoint mapping 'openpose' (built in: wheelpose23, blazepose33)"));
  EXPECT_EQ(error_csv(dir, long_csv(1, true), "blazepose33"),
            ":3: unknown joint 'neck_base' for mapping 'blazepose33'");
}

TEST(ImportKeypoints, ReportsBadJsonByEntry) {
  ScratchDir dir;
  EXPECT_THAT(error_json(dir, "{\"joints\": [\"pelvis\"], \"frames\": [[[1, NaN, 2]]]}"),
              HasSubstr(": not valid JSON: "));
  EXPECT_EQ(error_json(dir, "[1]"), ": top level must be an object");
  EXPECT_EQ(error_json(dir, "{\"frames\": []}"), ": needs a 'joints' array of joint names");
  EXPECT_EQ(error_json(dir, "{\"joints\": [\"pelvis\", \"tail\"], \"frames\": []}"),
            ": joints[1]: unknown joint 'tail' for mapping 'wheelpose23'");
  EXPECT_EQ(error_json(dir, "{\"joints\": [\"pelvis\", \"pelvis\"], \"frames\": []}"),
            ": joints[1]: joint 'pelvis' is listed twice");
  EXPECT_EQ(
      error_json(dir, "{\"joints\": [\"pelvis\"], \"frames\": [[[1,2,3]], [[1,2,3],[4,5,6]]]}"),
      ": frames[1]: expected an array of 1 points (one per entry of 'joints'), found 2 entries");
  EXPECT_EQ(error_json(dir, "{\"joints\": [\"pelvis\"], \"frames\": [[[1,2]]]}"),
            ": frames[0][0] (pelvis): expected [x, y, z]");
  EXPECT_EQ(error_json(dir, "{\"joints\": [\"pelvis\"], \"frames\": [[[1,null,2]]]}"),
            ": frames[0][0] (pelvis): coordinate 1 is null, not a number");
  EXPECT_EQ(error_json(dir, "{\"fps\": 0, \"joints\": [], \"frames\": []}"),
            ": 'fps' must be a positive number");
  EXPECT_EQ(error_json(dir, "{\"joints\": [\"pelvis\"], \"frames\": [[[1,2,3]]]}"),
            ": joint 'left_hip' (needed for left_hip by mapping 'wheelpose23') is missing");
}

}  // namespace
}  // namespace wheelpose::motion
