#include "generate/framing.h"

#include <gtest/gtest.h>

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
