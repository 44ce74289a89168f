#include "generate/framing.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "core/config.h"
#include "render/test_scenes.h"

namespace wheelpose::generate {
namespace {

using Eigen::Vector3f;
using render::testing::empty_scene;
using render::testing::material;
using render::testing::place;

// A person of ten keypoints in a row 5 m in front of the camera (x from −0.9 to 0.9 m), with
// every keypoint's occlusion tolerance 5 cm.
LabelPerson row_of_keypoints(std::uint16_t id, int count = 10) {
  LabelPerson p;
  p.instance_id = id;
  for (int k = 0; k < count; ++k) {
    p.keypoints.emplace_back(-0.9f + 0.2f * static_cast<float>(k), 0.0f, -5.0f);
    p.present.push_back(true);
    p.tolerance.push_back(0.05f);
  }
  return p;
}

// A box 3 m away covering x < 0: it hides the row's left half.
BuiltFrame half_hidden_row() {
  BuiltFrame frame;
  frame.scene = empty_scene(160, 120);
  frame.scene.meshes.push_back(scene::make_box({1.0f, 1.0f, 0.1f}, 1));
  frame.scene.materials.push_back(material({1, 1, 1}));
  frame.scene.instances.push_back(place(0, 0, {-1.0f, 0.0f, -3.0f}, 9, 1));
  frame.people.push_back(row_of_keypoints(1));
  return frame;
}

TEST(Framing, ShareOfKeypointsNoSurfaceHides) {
  const BuiltFrame frame = half_hidden_row();
  const render::Renderer renderer(frame.scene);
  const FramingScore score = score_framing(frame, renderer, frame.scene.camera, 5);
  EXPECT_EQ(score.people_judged, 1);
  EXPECT_DOUBLE_EQ(score.worst_visible_share, 0.5);
}

// Keypoints outside the picture, behind the camera or beyond a limb cut are not counted; a
// person with fewer than min_keypoints in the picture is not judged.
TEST(Framing, OnlyKeypointsInThePictureCount) {
  BuiltFrame frame = half_hidden_row();
  frame.people[0].keypoints[0].x() = -100.0f;  // far left of the picture (was hidden)
  frame.people[0].present[1] = false;          // a cut limb (was hidden)
  frame.people[0].keypoints[9].z() = 5.0f;     // behind the camera (was shown)
  LabelPerson few = row_of_keypoints(2, 3);    // three keypoints, all hidden by the box
  frame.people.push_back(few);
  const render::Renderer renderer(frame.scene);
  const FramingScore score = score_framing(frame, renderer, frame.scene.camera, 5);
  EXPECT_EQ(score.people_judged, 1);
  EXPECT_DOUBLE_EQ(score.worst_visible_share, 4.0 / 7.0);
  EXPECT_EQ(score_framing(frame, renderer, frame.scene.camera, 3).people_judged, 2);
  EXPECT_DOUBLE_EQ(score_framing(frame, renderer, frame.scene.camera, 3).worst_visible_share, 0);
  // Short of a share: the person showing 4 of 7 is short of 0.6, not of 0.5.
  EXPECT_EQ(score_framing(frame, renderer, frame.scene.camera, 3, 0.6).people_short, 2);
  EXPECT_EQ(score_framing(frame, renderer, frame.scene.camera, 3, 0.5).people_short, 1);
  EXPECT_EQ(score_framing(frame, renderer, frame.scene.camera, 5, 0.5).people_short, 0);
}

// A surface nearer in depth than the keypoint by no more than its tolerance does not hide it
// (the skin over a joint), by more it does: the labeler's rule.
TEST(Framing, ToleranceKeepsTheSkinOverAJointFromHidingIt) {
  BuiltFrame frame;
  frame.scene = empty_scene(160, 120);
  frame.scene.meshes.push_back(scene::make_box({3.0f, 3.0f, 0.01f}, 1));
  frame.scene.materials.push_back(material({1, 1, 1}));
  frame.scene.instances.push_back(place(0, 0, {0.0f, 0.0f, -4.96f}, 1, 1));  // 3 cm in front
  frame.people.push_back(row_of_keypoints(1));
  const render::Renderer renderer(frame.scene);
  EXPECT_DOUBLE_EQ(score_framing(frame, renderer, frame.scene.camera, 5).worst_visible_share, 1);
  for (float& t : frame.people[0].tolerance) t = 0.01f;
  EXPECT_DOUBLE_EQ(score_framing(frame, renderer, frame.scene.camera, 5).worst_visible_share, 0);
}

// A camera judged from another place sees past what stood in front of the first one, and what
// stands within kNearClearance of a camera is ignored: the builder leaves it out of that frame.
TEST(Framing, ACandidateCameraIsJudgedFromItsOwnPlace) {
  const BuiltFrame frame = half_hidden_row();
  const render::Renderer renderer(frame.scene);
  scene::Camera moved = frame.scene.camera;
  moved.position = Vector3f(0.0f, 0.0f, -2.7f);  // in front of the box, inside its clearance
  EXPECT_DOUBLE_EQ(score_framing(frame, renderer, moved, 5).worst_visible_share, 1.0);
  moved.position = Vector3f(0.0f, 0.0f, -1.0f);  // 2 m in front of the box: it still hides half
  EXPECT_DOUBLE_EQ(score_framing(frame, renderer, moved, 5).worst_visible_share, 0.5);
  // 2.5 m to the right the rays pass beside the box; the five keypoints right of x = −0.26 m
  // are in the picture, all shown.
  moved.position = Vector3f(2.5f, 0.0f, 0.0f);
  EXPECT_DOUBLE_EQ(score_framing(frame, renderer, moved, 5).worst_visible_share, 1.0);
}

// The draw kept: the first that leaves nobody short, else the fewest short and then the
// best-shown worst person; the first draw wins ties. Checked on a room whose four people stand
// around a pillar, so that cameras by different walls see them differently.
TEST(Framing, KeepsTheFirstDrawThatShowsEveryoneElseTheBest) {
  const Scenario scenario = Scenario::from_config(ConfigNode::load_string(
      "randomizers:\n  Environment: {room_probability: 1}\n  Camera: {room_walls: all}\n"
      "framing: {attempts: 6, min_visible_share: 0.9}\n",
      "framed.yaml"));
  RandomizerContext context;
  context.clip_names = {"a"};
  context.clip_durations = {1.0};
  context.width = 160;
  context.height = 120;
  BuiltFrame frame;
  frame.scene = empty_scene(160, 120);
  frame.scene.meshes.push_back(scene::make_box({0.3f, 1.0f, 0.3f}, 1));
  frame.scene.materials.push_back(material({1, 1, 1}));
  frame.scene.instances.push_back(place(0, 0, {0.0f, 1.0f, 0.0f}, 9, 1));
  for (const Vector3f& at :
       {Vector3f(-0.8f, 0, 0), Vector3f(0.8f, 0, 0), Vector3f(0, 0, 0.8f), Vector3f(0, 0, -0.8f)}) {
    LabelPerson p;
    for (int k = 0; k < 10; ++k) {
      p.keypoints.push_back(at + Vector3f(0, 0.2f + 0.15f * static_cast<float>(k), 0));
      p.present.push_back(true);
      p.tolerance.push_back(0.05f);
    }
    frame.people.push_back(p);
  }
  const render::Renderer renderer(frame.scene);
  int redrawn = 0, fallbacks = 0;
  for (int index = 0; index < 12; ++index) {
    const FrameDraft first = draft_frame(scenario, 3, index, context);
    std::vector<FramingScore> scores;
    for (int draw = 0; draw < 6; ++draw) {
      const FrameDraft d = draft_frame(scenario, 3, index, context, draw);
      scores.push_back(score_framing(frame, renderer, d.camera, 5, 0.9));
    }
    int expected = 0;
    const auto shows_everyone = std::find_if(
        scores.begin(), scores.end(), [](const FramingScore& f) { return f.people_short == 0; });
    if (shows_everyone != scores.end()) {
      expected = static_cast<int>(shows_everyone - scores.begin());
    } else {
      ++fallbacks;
      for (int draw = 1; draw < 6; ++draw) {
        const FramingScore &a = scores[static_cast<std::size_t>(draw)],
                           &b = scores[static_cast<std::size_t>(expected)];
        if (a.people_short < b.people_short ||
            (a.people_short == b.people_short && a.worst_visible_share > b.worst_visible_share))
          expected = draw;
      }
    }
    EXPECT_EQ(choose_camera_draw(scenario, 3, index, context, first, frame, renderer), expected)
        << "frame " << index;
    redrawn += expected > 0;
  }
  EXPECT_GT(redrawn, 0);    // the pillar hides someone from some first draws
  EXPECT_GT(fallbacks, 0);  // and from every draw of some frames
}

TEST(Framing, NobodyInViewScoresOne) {
  BuiltFrame frame = half_hidden_row();
  frame.people.clear();
  const render::Renderer renderer(frame.scene);
  const FramingScore score = score_framing(frame, renderer, frame.scene.camera, 5);
  EXPECT_EQ(score.people_judged, 0);
  EXPECT_EQ(score.worst_visible_share, 1.0);
}

}  // namespace
}  // namespace wheelpose::generate
