// Scenario loading, randomizer streams, sharding and the generated randomizer reference.

#include "generate/scenario.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>

#include "core/error.h"
#include "generate/runner.h"

namespace wheelpose::generate {
namespace {

std::string read(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

RandomizerContext small_context() {
  RandomizerContext ctx;
  ctx.clip_names = {"a", "b", "c"};
  ctx.clip_durations = {2.0, 3.5, 1.0};
  ctx.width = 160;
  ctx.height = 120;
  return ctx;
}

// The error reading `yaml` as the scenario file `name` gives, or "no error".
std::string message(const std::string& yaml, const std::string& name = "s.yaml") {
  try {
    Scenario::from_config(ConfigNode::load_string(yaml, name));
  } catch (const Error& e) {
    return std::string(e.what());
  }
  return std::string("no error");
}

TEST(Scenario, PaperPresetFileEqualsTheBuiltInDefaults) {
  const Scenario preset = Scenario::from_file(WHEELPOSE_SOURCE_DIR "/configs/wheelpose-paper.yaml");
  EXPECT_EQ(preset.to_json().dump(1), Scenario::defaults().to_json().dump(1));
  EXPECT_EQ(preset.randomizers.size(), Scenario::defaults().randomizers.size());
}

TEST(Scenario, ErrorsNameFileLineAndKey) {
  EXPECT_NE(message("randomizers:\n  Camera: {fov: 3}\n").find("s.yaml:2"), std::string::npos);
  EXPECT_NE(message("randomizers:\n  Camera: {fov: 3}\n").find("fov"), std::string::npos);
  EXPECT_NE(message("randomizers:\n  Nope: {}\n").find("unknown randomizer"), std::string::npos);
  EXPECT_NE(message("image: {width: 3}\n").find("width"), std::string::npos);
  EXPECT_NE(message("image: {spp: 2, light_samples: 3}\n").find("light_samples"),
            std::string::npos);
  EXPECT_NE(message("image: {denoise_radius: 40}\n").find("denoise_radius"), std::string::npos);
  EXPECT_NE(message("image: {adaptive_contrast: 2}\n").find("adaptive_contrast"),
            std::string::npos);
  EXPECT_NE(message("image: {bounce: sometimes}\n").find("bounce"), std::string::npos);
  EXPECT_NE(message("labels: {keypoint_template: nothing.json}\n").find("keypoint_template"),
            std::string::npos);
  EXPECT_NE(message("labels: {box: chair}\n").find("s.yaml:1"), std::string::npos);
  EXPECT_NE(message("labels: {box: chair}\n").find("'chair' is not person"), std::string::npos);
  EXPECT_NE(message("colour: red\n").find("colour"), std::string::npos);
  EXPECT_NE(message("randomizers:\n  HumanGeneration: {min_per_frame: 9, max_per_frame: 3}\n")
                .find("max_per_frame"),
            std::string::npos);
}

// labels.box reaches the labeler's options through the runner and the record; the default is
// not written, so earlier runs' scenarios read back the same.
TEST(Scenario, BoxConventionIsRecordedOnlyWhenItHoldsTheWheelchair) {
  const Scenario held = Scenario::from_config(
      ConfigNode::load_string("labels: {box: person_and_wheelchair}\n", "b.yaml"));
  EXPECT_TRUE(held.box_holds_wheelchair);
  EXPECT_EQ(held.to_json()["labels"]["box"], "person_and_wheelchair");
  const std::string recorded = "labels: " + held.to_json()["labels"].dump() + "\n";
  EXPECT_TRUE(Scenario::from_config(ConfigNode::load_string(recorded, "r")).box_holds_wheelchair);
  EXPECT_FALSE(Scenario::defaults().box_holds_wheelchair);
  EXPECT_FALSE(Scenario::defaults().to_json()["labels"].contains("box"));
}

// image.bounce reaches the renderer and the recorded scenario; off (the default) it is not
// written, so the scenarios recorded before it existed read back the same.
TEST(Scenario, BounceReachesTheRendererAndTheRecord) {
  const Scenario on =
      Scenario::from_config(ConfigNode::load_string("image: {bounce: true}\n", "b.yaml"));
  EXPECT_TRUE(on.render_options().bounce);
  EXPECT_EQ(on.to_json()["image"]["bounce"], true);
  const std::string recorded_image = "image: " + on.to_json()["image"].dump() + "\n";
  EXPECT_TRUE(Scenario::from_config(ConfigNode::load_string(recorded_image, "record")).bounce);
  EXPECT_FALSE(Scenario::defaults().render_options().bounce);
  EXPECT_FALSE(Scenario::defaults().to_json()["image"].contains("bounce"));
}

TEST(Scenario, DisabledRandomizersDoNotRun) {
  const Scenario s = Scenario::from_config(ConfigNode::load_string(
      "randomizers:\n  EmptyWheelchair: {enabled: false}\n  Sprite: {enabled: false}\n", "s"));
  for (const auto& a : s.randomizers) EXPECT_STRNE(a.entry->name, "EmptyWheelchair");
  EXPECT_EQ(s.randomizers.size(), Scenario::defaults().randomizers.size() - 1);
}

TEST(Scenario, FramesAreAPureFunctionOfSeedAndIndex) {
  const Scenario s = Scenario::defaults();
  const auto ctx = small_context();
  const FrameDraft a = draft_frame(s, 11, 5, ctx), b = draft_frame(s, 11, 5, ctx);
  ASSERT_EQ(a.people.size(), b.people.size());
  for (std::size_t i = 0; i < a.people.size(); ++i) {
    EXPECT_EQ(a.people[i].pool_slot, b.people[i].pool_slot);
    EXPECT_EQ(a.people[i].position, b.people[i].position);
    EXPECT_EQ(a.people[i].clip, b.people[i].clip);
  }
  EXPECT_EQ(a.camera, b.camera);
  EXPECT_FALSE(draft_frame(s, 11, 6, ctx).camera == a.camera);
  // The paper's people count: 5..12 per frame, clips from the context.
  for (int f = 0; f < 40; ++f) {
    const FrameDraft d = draft_frame(s, 3, f, ctx);
    EXPECT_GE(d.people.size(), 5u);
    EXPECT_LE(d.people.size(), 12u);
    for (const auto& p : d.people) {
      EXPECT_GE(p.clip, 0);
      EXPECT_LT(p.clip, 3);
      EXPECT_LE(p.time, ctx.clip_durations[static_cast<std::size_t>(p.clip)]);
    }
  }
}

TEST(Scenario, APoolMemberIsTheSamePersonInEveryFrameOfItsPool) {
  const Scenario s = Scenario::defaults();
  const auto ctx = small_context();
  std::map<int, double> age_of_slot;
  for (int f = 0; f < 30; ++f) {
    for (const auto& p : draft_frame(s, 5, f, ctx).people) {
      const auto [it, inserted] = age_of_slot.emplace(p.pool_slot, p.spec.params.age_years);
      EXPECT_EQ(it->second, p.spec.params.age_years) << "slot " << p.pool_slot;
    }
  }
  // The next pool (frame 400 on) draws new people.
  int changed = 0;
  for (const auto& p : draft_frame(s, 5, 400, ctx).people) {
    const auto it = age_of_slot.find(p.pool_slot);
    changed += it != age_of_slot.end() && it->second != p.spec.params.age_years;
  }
  EXPECT_GT(changed, 0);
}

TEST(Scenario, PowerHeadrestsAreDrawnOnlyWhenAsked) {
  const auto ctx = small_context();
  const Scenario plain = Scenario::defaults();
  const Scenario half = Scenario::from_config(ConfigNode::load_string(
      "randomizers: {Wheelchair: {power_headrest_probability: 0.5}}", "s.yaml"));
  int with = 0, without = 0;
  for (int f = 0; f < 40; ++f) {
    const FrameDraft a = draft_frame(plain, 5, f, ctx), b = draft_frame(half, 5, f, ctx);
    ASSERT_EQ(a.people.size(), b.people.size());
    for (std::size_t i = 0; i < a.people.size(); ++i) {
      EXPECT_FALSE(a.people[i].spec.chair_headrest.has_value());  // the default draws nothing
      ASSERT_TRUE(b.people[i].spec.chair_headrest.has_value());
      // The draw comes after the chair's type and colours, which stay as they were.
      EXPECT_EQ(a.people[i].spec.wheelchair, b.people[i].spec.wheelchair);
      EXPECT_EQ(a.people[i].chair_colours, b.people[i].chair_colours);
      (*b.people[i].spec.chair_headrest ? with : without) += 1;
    }
  }
  EXPECT_GT(with, 10);
  EXPECT_GT(without, 10);
  EXPECT_NE(message("randomizers: {Wheelchair: {power_headrest_probability: 1.5}}"), "no error");
}

TEST(Scenario, ReconfiguringOneRandomizerLeavesTheOthersDrawsAlone) {
  const Scenario a = Scenario::defaults();
  const Scenario b = Scenario::from_config(ConfigNode::load_string(
      "randomizers:\n  PostProcessVolume: {contrast: {uniform: [0, 1]}}\n", "s"));
  const auto ctx = small_context();
  const FrameDraft fa = draft_frame(a, 1, 2, ctx), fb = draft_frame(b, 1, 2, ctx);
  EXPECT_EQ(fa.camera, fb.camera);
  EXPECT_EQ(fa.sun, fb.sun);
  EXPECT_FALSE(fa.post == fb.post);
}

// A later camera draw (framing) redraws the camera alone: every other randomizer draws the same,
// and draw 0 is the frame as it always was.
TEST(Scenario, ALaterCameraDrawChangesOnlyTheCamera) {
  const Scenario s = Scenario::from_config(ConfigNode::load_string(
      "randomizers:\n  Environment: {room_probability: 1}\n  Camera: {room_walls: all}\n",
      "rooms.yaml"));
  const auto ctx = small_context();
  for (int frame = 0; frame < 6; ++frame) {
    const FrameDraft first = draft_frame(s, 4, frame, ctx);
    const FrameDraft again = draft_frame(s, 4, frame, ctx, 0);
    const FrameDraft second = draft_frame(s, 4, frame, ctx, 1);
    EXPECT_EQ(first.camera, again.camera);
    EXPECT_FALSE(second.camera == first.camera) << frame;
    EXPECT_EQ(second.sun, first.sun);
    EXPECT_EQ(second.post, first.post);
    ASSERT_EQ(second.people.size(), first.people.size());
    for (std::size_t i = 0; i < first.people.size(); ++i) {
      EXPECT_EQ(second.people[i].position, first.people[i].position);
      EXPECT_EQ(second.people[i].clip, first.people[i].clip);
    }
    EXPECT_EQ(draft_frame(s, 4, frame, ctx, 1).camera, second.camera);
  }
}

// TransformPlacement.room_heading_spread: a group in a room faces one way, each person within
// half the spread of the others' common heading; the full circle (default) draws as before and
// is not recorded.
TEST(Scenario, RoomHeadingSpreadTurnsTheGroupOneWay) {
  const auto ctx = small_context();
  auto rooms = [](const std::string& placement) {
    return Scenario::from_config(ConfigNode::load_string(
        "randomizers:\n  Environment: {room_probability: 1}\n  HumanGeneration: "
        "{min_per_frame: 4, max_per_frame: 4}\n  TransformPlacement: " +
            placement + "\n",
        "rooms.yaml"));
  };
  const auto heading = [](const PersonDraft& p) {
    const Eigen::Vector3f forward = p.rotation * Eigen::Vector3f::UnitZ();
    return std::atan2(forward.x(), forward.z());
  };
  // The largest angle between two of a frame's people's headings, in degrees.
  const auto widest = [&](const FrameDraft& d) {
    double most = 0;
    for (const PersonDraft& a : d.people) {
      for (const PersonDraft& b : d.people) {
        const double diff = std::remainder(heading(a) - heading(b), 2 * std::numbers::pi);
        most = std::max(most, std::abs(diff) * 180 / std::numbers::pi);
      }
    }
    return most;
  };
  const Scenario narrow = rooms("{room_heading_spread: 60}");
  const Scenario full = rooms("{}");
  double widest_narrow = 0, widest_full = 0;
  for (int frame = 0; frame < 40; ++frame) {
    const FrameDraft narrowed = draft_frame(narrow, 5, frame, ctx);
    const FrameDraft full_circle = draft_frame(full, 5, frame, ctx);
    ASSERT_GE(narrowed.people.size(), 2u);
    widest_narrow = std::max(widest_narrow, widest(narrowed));
    widest_full = std::max(widest_full, widest(full_circle));
    // Only the headings change: the same places.
    ASSERT_EQ(narrowed.people.size(), full_circle.people.size());
    for (std::size_t i = 0; i < narrowed.people.size(); ++i)
      EXPECT_EQ(narrowed.people[i].position, full_circle.people[i].position);
  }
  EXPECT_LE(widest_narrow, 60.0 + 1e-3);
  EXPECT_GT(widest_full, 150.0);
  EXPECT_EQ(narrow.to_json()["randomizers"]["TransformPlacement"]["room_heading_spread"], 60.0);
  EXPECT_FALSE(full.to_json()["randomizers"]["TransformPlacement"].contains("room_heading_spread"));
  EXPECT_NE(message("randomizers:\n  TransformPlacement: {room_heading_spread: 400}\n")
                .find("room_heading_spread"),
            std::string::npos);
}

// With `room_walls: all` the camera stands by a side wall about half of the time, looking into
// the room; by default always by an end wall.
TEST(Scenario, RoomCameraStandsByTheWallsItIsGiven) {
  const auto ctx = small_context();
  auto side_wall_share = [&](const std::string& walls) {
    const Scenario s = Scenario::from_config(ConfigNode::load_string(
        "randomizers:\n  Environment: {room_probability: 1}\n  Camera: {room_walls: " + walls +
            "}\n",
        "rooms.yaml"));
    int side = 0;
    constexpr int kFrames = 200;
    for (int frame = 0; frame < kFrames; ++frame) {
      const FrameDraft d = draft_frame(s, 9, frame, ctx);
      const Eigen::Vector2f half = 0.5f * d.room.size;
      const Eigen::Vector3f& eye = d.camera.position;
      const bool by_side = std::abs(std::abs(eye.x()) - 0.9f * half.x()) < 1e-4f;
      const bool by_end = std::abs(std::abs(eye.z()) - 0.9f * half.y()) < 1e-4f;
      EXPECT_TRUE(by_side || by_end) << walls << " frame " << frame;
      side += by_side;
    }
    return static_cast<double>(side) / kFrames;
  };
  EXPECT_EQ(side_wall_share("ends"), 0.0);
  EXPECT_NEAR(side_wall_share("all"), 0.5, 0.1);
  EXPECT_EQ(Scenario::defaults().to_json()["randomizers"]["Camera"].count("room_walls"), 0u);
}

// framing: read, range-checked, recorded only when on (so earlier runs' records read back the
// same), and read back from the record.
TEST(Scenario, FramingIsCheckedAndRecordedOnlyWhenOn) {
  EXPECT_NE(message("framing: {attempts: 0}\n").find("attempts"), std::string::npos);
  EXPECT_NE(message("framing: {attempts: 0}\n", "f.yaml").find("f.yaml:1"), std::string::npos);
  EXPECT_NE(message("framing: {min_visible_share: 1.5}\n").find("min_visible_share"),
            std::string::npos);
  EXPECT_NE(message("framing: {tries: 3}\n").find("tries"), std::string::npos);
  EXPECT_NE(message("randomizers:\n  Camera: {room_walls: some}\n").find("room_walls"),
            std::string::npos);
  const Scenario on = Scenario::from_config(ConfigNode::load_string(
      "framing: {attempts: 6, min_visible_share: 0.8, min_keypoints: 7}\n", "f.yaml"));
  EXPECT_EQ(on.framing.attempts, 6);
  const std::string recorded = "framing: " + on.to_json()["framing"].dump() + "\n";
  const Scenario back = Scenario::from_config(ConfigNode::load_string(recorded, "record"));
  EXPECT_EQ(back.framing.attempts, 6);
  EXPECT_EQ(back.framing.min_visible_share, 0.8);
  EXPECT_EQ(back.framing.min_keypoints, 7);
  EXPECT_FALSE(Scenario::defaults().to_json().contains("framing"));
  EXPECT_FALSE(Scenario::from_config(ConfigNode::load_string("framing: {attempts: 1}\n", "f"))
                   .to_json()
                   .contains("framing"));
}

TEST(Sharding, ShardsPartitionTheFrames) {
  for (std::int64_t n : {1, 5, 7, 100}) {
    for (int count : {1, 2, 3, 8}) {
      std::int64_t next = 0;
      for (int i = 0; i < count; ++i) {
        const auto [first, end] = shard_range(n, i, count);
        EXPECT_EQ(first, next);
        EXPECT_GE(end, first);
        next = end;
      }
      EXPECT_EQ(next, n);
    }
  }
}

TEST(PoissonDisk, PointsKeepTheirSeparationAndFillTheArea) {
  RandomStream rng(9, {"test"});
  const auto points = poisson_disk(15, 15, 2.5f, rng);
  ASSERT_GT(points.size(), 15u);  // a 15 m square holds ~25 points 2.5 m apart
  for (std::size_t i = 0; i < points.size(); ++i) {
    EXPECT_GE(points[i].x(), 0);
    EXPECT_LT(points[i].x(), 15);
    for (std::size_t j = i + 1; j < points.size(); ++j)
      EXPECT_GE((points[i] - points[j]).norm(), 2.5f);
  }
}

TEST(RandomizerReference, GenerateGuideSectionIsTheGeneratedReference) {
  const std::string readme = read(WHEELPOSE_SOURCE_DIR "/docs/commands/generate.md");
  const std::string begin = "<!-- randomizer-reference:begin -->\n";
  const std::string end = "<!-- randomizer-reference:end -->";
  const auto b = readme.find(begin), e = readme.find(end);
  ASSERT_NE(b, std::string::npos);
  ASSERT_NE(e, std::string::npos);
  EXPECT_EQ(readme.substr(b + begin.size(), e - b - begin.size()), randomizer_reference_markdown())
      << "regenerate with: wheelpose generate --list-randomizers";
}

}  // namespace
}  // namespace wheelpose::generate
