#include "motion/npy.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"
#include "motion/import_npy.h"
#include "motion/import_test_util.h"

namespace wheelpose::motion {
namespace {

using ::testing::HasSubstr;
using testing::npy_bytes;
using testing::ScratchDir;

std::string error_of(const std::string& bytes) {
  try {
    parse_npy(bytes, "x.npy");
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(Npy, ReadsLittleEndianFloat32Version1) {
  NpyArray a = parse_npy(npy_bytes("<f4", {2, 3}, {1.5, -2.25, 0, 4, 5, 6.125}), "x.npy");
  EXPECT_EQ(a.shape, (std::vector<std::size_t>{2, 3}));
  EXPECT_EQ(a.values, (std::vector<double>{1.5, -2.25, 0, 4, 5, 6.125}));
  EXPECT_EQ(a.descr, "<f4");
}

TEST(Npy, ReadsBigEndianFloat64AndVersions2And3) {
  for (int major : {2, 3}) {
    NpyArray a = parse_npy(npy_bytes(">f8", {3}, {0.1, -1e300, 7}, major), "x.npy");
    EXPECT_EQ(a.shape, (std::vector<std::size_t>{3}));
    EXPECT_EQ(a.values, (std::vector<double>{0.1, -1e300, 7})) << "version " << major;
  }
  NpyArray b = parse_npy(npy_bytes(">f4", {1}, {3.5}), "x.npy");
  EXPECT_EQ(b.values[0], 3.5);
}

TEST(Npy, NativeOrderMarkersAreAccepted) {
  std::string bytes = npy_bytes("<f8", {1}, {2.5});
  std::string native = bytes;
  native.replace(native.find("'<f8'"), 5, "'=f8'");
  EXPECT_EQ(parse_npy(native, "x.npy").values[0], 2.5);
  native.replace(native.find("'=f8'"), 5, "'|f8'");
  EXPECT_EQ(parse_npy(native, "x.npy").values[0], 2.5);
}

TEST(Npy, RejectsMalformedFiles) {
  EXPECT_THAT(error_of("PK\x03\x04 not numpy"), HasSubstr("not a NumPy .npy file"));
  EXPECT_THAT(error_of(npy_bytes("<f4", {2}, {1, 2}, 1, true)),
              HasSubstr("fortran order arrays are not supported"));
  std::string full = npy_bytes("<f4", {4}, {1, 2, 3, 4});
  EXPECT_THAT(error_of(full.substr(0, full.size() - 3)),
              HasSubstr("truncated .npy file: shape needs 16 data bytes, file has 13"));
  EXPECT_THAT(error_of(full.substr(0, 20)), HasSubstr("truncated .npy file (header"));
  EXPECT_THAT(error_of(full + "xx"), HasSubstr("2 bytes after the array data"));
  EXPECT_THAT(error_of(npy_bytes("<i4", {1}, {1})), HasSubstr("unsupported dtype '<i4'"));
  std::string v9 = full;
  v9[6] = 9;
  EXPECT_THAT(error_of(v9), HasSubstr("unsupported .npy format version 9.0"));
  std::string no_shape = full;
  no_shape.replace(no_shape.find("'shape'"), 7, "'shope'");
  EXPECT_THAT(error_of(no_shape), HasSubstr("unexpected entry 'shope'"));
  EXPECT_THAT(error_of(full), ::testing::IsEmpty());
}

// SMPL-22 positions where joint j of frame t sits at (j, 10 t, -j).
std::vector<double> smpl_values(std::size_t frames, std::size_t joints) {
  std::vector<double> v;
  for (std::size_t t = 0; t < frames; ++t) {
    for (std::size_t j = 0; j < joints; ++j) {
      v.insert(v.end(), {double(j), 10.0 * double(t), -double(j)});
    }
  }
  return v;
}

TEST(ImportNpy, MapsSmpl22JointsToOurs) {
  ScratchDir dir;
  auto path = dir.write("walk.npy", npy_bytes("<f4", {2, 22, 3}, smpl_values(2, 22)));
  PositionClip clip = import_npy(path, {});
  EXPECT_EQ(clip.name, "walk");
  EXPECT_EQ(clip.source, path.string());
  EXPECT_EQ(clip.fps, 20.0);
  ASSERT_EQ(clip.frames.size(), 2u);
  auto smpl = [](int j, int t) { return Eigen::Vector3d(j, 10.0 * t, -j); };
  const Pose& f1 = clip.frames[1];
  // Indices of reference §1.1: 3 spine1, 6 spine2, 9 spine3, 10/11 feet, 12 neck, 15 head.
  EXPECT_EQ(f1[kPelvis], smpl(0, 1));
  EXPECT_EQ(f1[kLeftHip], smpl(1, 1));
  EXPECT_EQ(f1[kSpine], smpl(3, 1));
  EXPECT_EQ(f1[kLeftKnee], smpl(4, 1));
  EXPECT_EQ(f1[kRightKnee], smpl(5, 1));
  EXPECT_EQ(f1[kChest], smpl(6, 1));
  EXPECT_EQ(f1[kLeftAnkle], smpl(7, 1));
  EXPECT_EQ(f1[kUpperChest], smpl(9, 1));
  EXPECT_EQ(f1[kRightToe], smpl(11, 1));
  EXPECT_EQ(f1[kHeadBase], smpl(12, 1));
  EXPECT_EQ(f1[kLeftClavicle], smpl(13, 1));
  EXPECT_EQ(f1[kHeadTop], smpl(15, 1));
  EXPECT_EQ(f1[kRightWrist], smpl(21, 1));
  EXPECT_EQ(f1[kNeckBase], Eigen::Vector3d(13.5, 10, -13.5));  // mean of the collars
}

TEST(ImportNpy, UsesTheNeckBaseOf23JointArraysAndOptions) {
  ScratchDir dir;
  auto path = dir.write("t2m.npy", npy_bytes("<f8", {1, 23, 3}, smpl_values(1, 23)));
  ImportOptions options;
  options.fps = 25;
  options.unit_scale = 0.5;
  PositionClip clip = import_npy(path, options);
  EXPECT_EQ(clip.fps, 25.0);
  EXPECT_EQ(clip.frames[0][kNeckBase], Eigen::Vector3d(11, 0, -11));
  EXPECT_EQ(clip.frames[0][kHeadTop], Eigen::Vector3d(7.5, 0, -7.5));
}

TEST(ImportNpy, RejectsWrongShapesAndNonFiniteValues) {
  ScratchDir dir;
  auto expect_error = [&](const std::string& bytes, const std::string& message) {
    auto path = dir.write("bad.npy", bytes);
    try {
      import_npy(path, {});
      ADD_FAILURE() << "no error for " << message;
    } catch (const Error& e) {
      EXPECT_THAT(e.what(), HasSubstr(path.string()));
      EXPECT_THAT(e.what(), HasSubstr(message));
    }
  };
  expect_error(npy_bytes("<f4", {2, 21, 3}, smpl_values(2, 21)),
               "array shape (2, 21, 3) is not (frames, 22, 3)");
  expect_error(npy_bytes("<f4", {22, 3}, smpl_values(1, 22)), "array shape (22, 3)");
  expect_error(npy_bytes("<f4", {0, 22, 3}, {}), "no frames");
  std::vector<double> v = smpl_values(2, 22);
  v[(22 + 5) * 3 + 1] = std::nan("");
  expect_error(npy_bytes("<f4", {2, 22, 3}, v), "frame 1, joint 5 (right_knee) is not finite");
  std::string truncated = npy_bytes("<f4", {2, 22, 3}, smpl_values(2, 22));
  expect_error(truncated.substr(0, truncated.size() - 8), "truncated .npy file");
}

}  // namespace
}  // namespace wheelpose::motion
