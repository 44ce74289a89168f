#include "motion/library.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <set>

#include "core/error.h"
#include "motion/plausibility.h"

namespace wheelpose::motion {
namespace {

using ::testing::HasSubstr;

std::string error_of(const std::string& yaml) {
  try {
    parse_motion_definition(yaml, "data/motions/bad.yaml");
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(Library, HasAtLeastFortyMotionsSortedById) {
  const auto motions = library_motions();
  EXPECT_GE(motions.size(), 40u);
  for (std::size_t i = 1; i < motions.size(); ++i) EXPECT_LT(motions[i - 1].id, motions[i].id);
  for (const auto& m : motions) EXPECT_FALSE(m.description.empty()) << m.id;
}

TEST(Library, CoversEveryActivityClassAndTheMissingMotions) {
  std::set<std::string> classes;
  for (const auto& m : library_motions()) classes.insert(m.activity_class);
  for (const char* c :
       {"talking", "wheelchair skills", "daily routine", "dance", "basketball", "tennis",
        "extreme sports", "general sports", "household chores", "shopping", "cooking", "travel",
        "photoshoot", "rugby", "pickleball", "stretches", "clapping", "typing", "dressing"}) {
    EXPECT_TRUE(classes.count(c)) << "no motion of class " << c;
  }
  // The wheelchair skills the paper's users named.
  std::set<std::string> ids;
  for (const auto& m : library_motions()) ids.insert(m.id);
  for (const char* id : {"push_rims_forward", "wheelie", "turn_in_place"}) {
    EXPECT_TRUE(ids.count(id)) << id;
  }
}

TEST(Library, EmbedsEveryYamlFileOfTheSourceTree) {
  std::size_t files = 0;
  for (const auto& entry :
       std::filesystem::directory_iterator(std::string(WHEELPOSE_SOURCE_DIR) + "/data/motions")) {
    if (entry.path().extension() == ".yaml") ++files;
  }
  EXPECT_EQ(library_motions().size(), files);
}

// The central property: every variant of every motion is anatomically plausible.
TEST(Library, EveryClipIsPlausibleFiniteAndTwoToTenSeconds) {
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    for (const PositionClip& clip : library_clips(seed)) {
      EXPECT_EQ(clip.source, "library:" + clip.name);
      EXPECT_EQ(clip.fps, 30.0);
      const double seconds = clip.frames.size() / clip.fps;
      EXPECT_GE(seconds, 2.0) << clip.name;
      EXPECT_LE(seconds, 10.0) << clip.name;
      for (const Pose& pose : clip.frames) {
        for (const auto& joint : pose) ASSERT_TRUE(joint.allFinite()) << clip.name;
      }
      const auto problems = plausibility_problems(clip.frames);
      EXPECT_THAT(problems, ::testing::IsEmpty()) << clip.name << " seed " << seed;
    }
  }
}

// No jumps: joints move less than 0.2 m per frame (6 m/s at 30 fps), also across the wrap of
// a looping clip, whose last frame must flow into its first.
TEST(Library, ClipsAreSmoothAndLoopsWrapSeamlessly) {
  for (const PositionClip& clip : library_clips(1)) {
    const bool loop = library_definition(clip.name).loop;
    double worst_step = 0.0;
    for (std::size_t f = 1; f < clip.frames.size(); ++f) {
      for (int j = 0; j < kJointCount; ++j) {
        worst_step = std::max(worst_step, (clip.frames[f][j] - clip.frames[f - 1][j]).norm());
      }
    }
    EXPECT_LT(worst_step, 0.2) << clip.name;
    if (loop) {
      double wrap = 0.0;
      for (int j = 0; j < kJointCount; ++j) {
        wrap = std::max(wrap, (clip.frames.front()[j] - clip.frames.back()[j]).norm());
      }
      EXPECT_LE(wrap, std::max(worst_step, 1e-9) * 1.01) << clip.name;
    }
  }
}

TEST(Library, SameSeedIsBitwiseIdenticalAndSeedsDiffer) {
  const PositionClip a = library_clip("tennis_forehand", 7);
  const PositionClip b = library_clip("tennis_forehand", 7);
  ASSERT_EQ(a.frames.size(), b.frames.size());
  EXPECT_EQ(std::memcmp(a.frames.data(), b.frames.data(), a.frames.size() * sizeof(Pose)), 0);
  int differing = 0;
  for (const auto& m : library_motions()) {
    const PositionClip x = library_clip(m.id, 1);
    const PositionClip y = library_clip(m.id, 2);
    if (x.frames.size() != y.frames.size() ||
        std::memcmp(x.frames.data(), y.frames.data(), x.frames.size() * sizeof(Pose)) != 0) {
      ++differing;
    }
  }
  EXPECT_EQ(differing, static_cast<int>(library_motions().size()));
}

TEST(Library, VariantsStayInTheirRangesAndBothMirrorsOccur) {
  int mirrored = 0;
  int total = 0;
  for (const auto& m : library_motions()) {
    for (std::uint64_t seed = 1; seed <= 5; ++seed) {
      const MotionVariant v = library_variant(m.id, seed);
      EXPECT_GE(v.speed, 0.8);
      EXPECT_LT(v.speed, 1.25);
      EXPECT_GE(v.amplitude, 0.85);
      EXPECT_LT(v.amplitude, 1.1);
      mirrored += v.mirrored;
      ++total;
    }
  }
  EXPECT_GT(mirrored, total / 4);
  EXPECT_LT(mirrored, 3 * total / 4);
}

TEST(Library, MirroredVariantIsTheMirrorImage) {
  for (const std::string id : {"basketball_dribble", "tennis_forehand", "turn_in_place"}) {
    std::uint64_t seed = 1;
    while (!library_variant(id, seed).mirrored) ++seed;
    const PositionClip mirrored = library_clip(id, seed);
    MotionVariant plain_variant = library_variant(id, seed);
    plain_variant.mirrored = false;
    const PositionClip plain = synthesize_motion(library_definition(id), plain_variant);
    ASSERT_EQ(mirrored.frames.size(), plain.frames.size()) << id;
    for (std::size_t f = 0; f < plain.frames.size(); ++f) {
      for (int j = 0; j < kJointCount; ++j) {
        const Eigen::Vector3d& p = plain.frames[f][mirror_joint(j)];
        const Eigen::Vector3d& m = mirrored.frames[f][j];
        ASSERT_EQ(m.x(), -p.x()) << id << " frame " << f << " joint " << j;
        ASSERT_EQ(m.y(), p.y());
        ASSERT_EQ(m.z(), p.z());
      }
    }
    // Authored right-handed: the plain variant's right hand and the mirror's left hand lead.
    const std::size_t mid = plain.frames.size() / 2;
    EXPECT_EQ(plain.frames[mid][kRightWrist].x(), -mirrored.frames[mid][kLeftWrist].x()) << id;
  }
}

TEST(Library, MirrorPoseSwapsSidesAndNegatesX) {
  Pose p;
  for (int j = 0; j < kJointCount; ++j) p[j] = Eigen::Vector3d(j + 0.5, 2.0 * j, -j);
  const Pose m = mirror_pose(p);
  const double r = kRightWrist;
  EXPECT_EQ(m[kLeftWrist], Eigen::Vector3d(-(r + 0.5), 2.0 * r, -r));
  EXPECT_EQ(m[kPelvis], Eigen::Vector3d(-0.5, 0.0, 0.0));
  const Pose back = mirror_pose(m);
  for (int j = 0; j < kJointCount; ++j) EXPECT_EQ(back[j], p[j]);
}

TEST(Library, AnglesRoundTripThroughPositions) {
  // Authored angles come back out of the positions when measured by the plausibility module.
  const MotionDefinition m = parse_motion_definition(
      "id: probe\nclass: talking\ndescription: probe\nduration: 3\n"
      "keyframes:\n"
      "  - {t: 0, left_elbow_flexion: 60, right_elbow_flexion: 100, right_shoulder_elevation: 30,"
      " right_shoulder_plane: 70, right_shoulder_rotation: 35, head_nod: 20, trunk_twist: 30,"
      " left_clavicle_elevation: 20, left_shoulder_elevation: 90, left_shoulder_plane: -40}\n",
      "inline");
  const PositionClip clip = synthesize_motion(m, {});
  const PoseAngles a = measure_pose_angles(clip.frames[0]);
  EXPECT_NEAR(a.elbow_flexion[0], 60.0, 1e-6);
  EXPECT_NEAR(a.elbow_flexion[1], 100.0, 1e-6);
  EXPECT_NEAR(a.humeral_rotation[1], 35.0, 1e-6);
  EXPECT_NEAR(a.neck_flexion, 20.0, 1e-6);
  EXPECT_NEAR(a.trunk_twist, 30.0, 1e-6);
  EXPECT_NEAR(a.clavicle_elevation[0], 20.0, 1e-6);
  EXPECT_NEAR(a.arm_extension[0], 40.0, 1e-6);  // sideways-and-back arm at 90 elevation
  // Pelvis fixed, bones at their default lengths.
  EXPECT_EQ(clip.frames[0][kPelvis], Eigen::Vector3d(0, 0.5, 0));
  EXPECT_NEAR((clip.frames[0][kLeftWrist] - clip.frames[0][kLeftElbow]).norm(),
              default_bone_length(kLeftWrist), 1e-12);
}

TEST(Library, GoldenRestPositionsAndFrameCounts) {
  // Every angle zero: upright trunk, arms hanging straight down, seated legs.
  const MotionDefinition m = parse_motion_definition(
      "id: rest\nclass: talking\ndescription: rest\nduration: 3\nfps: 20\n"
      "keyframes:\n  - {t: 0, head_nod: 0}\n",
      "inline");
  const PositionClip clip = synthesize_motion(m, {});
  EXPECT_EQ(clip.frames.size(), 61u);  // 3 s at 20 fps plus the end frame (not a loop)
  const Pose& p = clip.frames[0];
  EXPECT_TRUE(p[kNeckBase].isApprox(Eigen::Vector3d(0, 0.95, 0), 1e-12));
  EXPECT_TRUE(p[kLeftShoulder].isApprox(Eigen::Vector3d(0.15, 0.95, 0), 1e-12));
  EXPECT_TRUE(p[kLeftWrist].isApprox(Eigen::Vector3d(0.15, 0.43, 0), 1e-12));
  EXPECT_TRUE(p[kRightKnee].isApprox(Eigen::Vector3d(-0.1, 0.5, 0.4), 1e-12));
  EXPECT_TRUE(p[kRightAnkle].isApprox(Eigen::Vector3d(-0.1, 0.09, 0.4), 1e-12));
  // Twice as fast: half the frames. Loops have no repeated end frame.
  EXPECT_EQ(synthesize_motion(m, {2.0, 1.0, false}).frames.size(), 31u);
  MotionDefinition loop = m;
  loop.loop = true;
  EXPECT_EQ(synthesize_motion(loop, {}).frames.size(), 60u);
}

TEST(Library, InterpolatesThroughKeysAndScalesAmplitudeAboutTheMiddle) {
  const MotionDefinition m = parse_motion_definition(
      "id: k\nclass: talking\ndescription: k\nduration: 4\n"
      "keyframes:\n  - {t: 0, left_elbow_flexion: 20}\n  - {t: 0.5, left_elbow_flexion: 100}\n"
      "  - {t: 1, left_elbow_flexion: 60}\n",
      "inline");
  EXPECT_DOUBLE_EQ(motion_channels_at(m, 0.0, 1.0).at("left_elbow_flexion"), 20.0);
  EXPECT_DOUBLE_EQ(motion_channels_at(m, 0.5, 1.0).at("left_elbow_flexion"), 100.0);
  EXPECT_DOUBLE_EQ(motion_channels_at(m, 1.0, 1.0).at("left_elbow_flexion"), 60.0);
  // Middle of the range is 60: amplitude 0.5 maps 100 -> 80 and 20 -> 40.
  EXPECT_DOUBLE_EQ(motion_channels_at(m, 0.5, 0.5).at("left_elbow_flexion"), 80.0);
  EXPECT_DOUBLE_EQ(motion_channels_at(m, 0.0, 0.5).at("left_elbow_flexion"), 40.0);
  // Smooth and between the neighbours on the rising segment.
  const double quarter = motion_channels_at(m, 0.25, 1.0).at("left_elbow_flexion");
  EXPECT_GT(quarter, 20.0);
  EXPECT_LT(quarter, 100.0);
}

TEST(Library, LoopsWrapAroundAndOscillatorsAdd) {
  const MotionDefinition m = parse_motion_definition(
      "id: l\nclass: clapping\ndescription: l\nduration: 4\nloop: true\n"
      "keyframes:\n  - {t: 0, both_elbow_flexion: 90}\n"
      "oscillators:\n  - {channel: right_elbow_flexion, amplitude: 10, cycles: 2}\n",
      "inline");
  EXPECT_NEAR(motion_channels_at(m, 0.125, 1.0).at("right_elbow_flexion"), 100.0, 1e-9);
  EXPECT_NEAR(motion_channels_at(m, 0.375, 1.0).at("right_elbow_flexion"), 80.0, 1e-9);
  EXPECT_NEAR(motion_channels_at(m, 0.375, 1.0).at("left_elbow_flexion"), 90.0, 1e-9);
  EXPECT_NEAR(motion_channels_at(m, 1.125, 1.0).at("right_elbow_flexion"), 100.0, 1e-9);
}

TEST(Library, UnknownIdThrows) { EXPECT_THROW(library_clip("no_such_motion", 1), Error); }

TEST(Library, MalformedDefinitionsNameFileKeyAndProblem) {
  const std::string head = "id: bad\nclass: talking\ndescription: d\n";
  EXPECT_THAT(error_of(head + "keyframes:\n  - {t: 0, left_elbow_flexion: 170}\n"),
              HasSubstr("data/motions/bad.yaml:5: key 'keyframes[0].left_elbow_flexion': "
                        "channel 'left_elbow_flexion' = 170 is outside its allowed range"));
  EXPECT_THAT(error_of(head + "keyframes:\n  - {t: 0, left_knee_flexion: 10}\n"),
              HasSubstr("unknown channel 'left_knee_flexion'"));
  EXPECT_THAT(error_of(head + "keyframes:\n  - {t: 0.5, head_nod: 1}\n  - {t: 0.2, head_nod: 2}\n"),
              HasSubstr("keyframe times of channel 'head_nod' must increase"));
  EXPECT_THAT(error_of(head + "keyframes: []\n"), HasSubstr("non-empty list"));
  EXPECT_THAT(error_of(head + "keyframes:\n  - {head_nod: 1}\n"), HasSubstr("'t'"));
  EXPECT_THAT(error_of("id: bad\nclass: knitting\ndescription: d\nkeyframes:\n  - {t: 0}\n"),
              HasSubstr("'knitting' is not one of"));
  EXPECT_THAT(error_of("id: other\nclass: talking\ndescription: d\nkeyframes:\n  - {t: 0}\n"),
              HasSubstr("must equal the file name 'bad'"));
  EXPECT_THAT(error_of(head + "speed: 2\nkeyframes:\n  - {t: 0}\n"), HasSubstr("speed"));
  EXPECT_THAT(error_of(head + "loop: true\nkeyframes:\n  - {t: 0, head_nod: 1}\n"
                              "  - {t: 1, head_nod: 5}\n"),
              HasSubstr("equal values at t=0 and t=1"));
  EXPECT_THAT(error_of(head + "loop: true\nkeyframes:\n  - {t: 0}\noscillators:\n"
                              "  - {channel: head_nod, amplitude: 5, cycles: 1.5}\n"),
              HasSubstr("whole number of cycles"));
  EXPECT_THAT(error_of(head + "keyframes:\n  - {t: 0}\noscillators:\n"
                              "  - {channel: head_nod, amplitude: 5, start: 0.6, end: 0.4}\n"),
              HasSubstr("'end' must be after 'start'"));
  EXPECT_THAT(error_of(head + "keyframes: [\n"), HasSubstr("YAML syntax error"));
  EXPECT_THAT(error_of("id: Bad-Id\nclass: talking\ndescription: d\nkeyframes:\n  - {t: 0}\n"),
              HasSubstr("lower-case"));
}

}  // namespace
}  // namespace wheelpose::motion
