#include "generate/labeler.h"

#include <gtest/gtest.h>

#include <cmath>

#include "scene/projector.h"

namespace wheelpose::generate {
namespace {

using Eigen::Vector3f;

// A 64×48 camera at the origin looking down −z (vfov 60°), a 2 m square of instance 1 at
// z = −5, and hand-made buffers: the labeler reads visibility from the depth buffer and the
// visible mask from the instance buffer, whatever the scene shows.
struct Fixture {
  BuiltFrame frame;
  render::FrameBuffers buffers;
  scene::Projector proj{scene::Camera{}};

  Fixture() {
    scene::Camera& cam = frame.scene.camera;
    cam.position = Vector3f::Zero();
    cam.width = 64;
    cam.height = 48;
    proj = scene::Projector(cam);
    scene::Mesh square;
    square.positions = {{-1, -1, -5}, {1, -1, -5}, {1, 1, -5}, {-1, 1, -5}};
    square.triangles = {{0, 1, 2}, {0, 2, 3}};
    frame.scene.meshes.push_back(square);
    scene::Instance inst;
    inst.mesh = 0;
    inst.instance_id = 1;
    frame.scene.instances.push_back(inst);

    LabelPerson person;
    person.instance_id = 1;
    person.keypoints = {{0, 0, -5}, {0.2f, 0.1f, -5}, {0, 0, 1}, {0.1f, 0, -5}};
    person.present = {true, true, true, false};
    person.tolerance = {0.05f, 0.05f, 0.05f, 0.05f};
    person.attributes["motion_id"] = "wave";
    frame.people.push_back(person);
    LabelPerson tiny = person;  // 10 visible pixels: dropped
    tiny.instance_id = 2;
    frame.people.push_back(tiny);

    buffers.instance = cv::Mat::zeros(48, 64, CV_16U);
    buffers.instance(cv::Rect(28, 20, 10, 8)).setTo(1);  // 80 pixels
    buffers.instance(cv::Rect(0, 0, 10, 1)).setTo(2);
    buffers.depth = cv::Mat::zeros(48, 64, CV_32F);
  }
};

TEST(Labeler, KeypointsProjectAndTakeTheirVisibilityFromDepth) {
  Fixture fx;
  // Keypoint 0 at the image centre with its own surface 2 cm in front (within tolerance);
  // keypoint 1 behind a surface 2 m nearer.
  const Eigen::Vector2f p1 = fx.proj.project(fx.proj.to_camera(fx.frame.people[0].keypoints[1]));
  fx.buffers.depth.at<float>(24, 32) = 4.98f;
  fx.buffers.depth.at<float>(static_cast<int>(std::floor(p1.y())),
                             static_cast<int>(std::floor(p1.x()))) = 3.0f;
  const FrameLabels labels = label_frame(fx.frame, fx.buffers, LabelOptions{});
  EXPECT_EQ(labels.dropped_people, 1);
  ASSERT_EQ(labels.annotations.size(), 1u);
  const nlohmann::ordered_json& a = labels.annotations[0];
  const auto kp = a["keypoints"].get<std::vector<double>>();
  ASSERT_EQ(kp.size(), 12u);
  // The centre of a 64×48 image is (32, 24) in continuous pixel coordinates.
  EXPECT_EQ(kp[0], 32.0);
  EXPECT_EQ(kp[1], 24.0);
  EXPECT_EQ(kp[2], 2);
  EXPECT_NEAR(kp[3], 32 + fx.proj.f * 0.2 / 5, 1e-3);
  EXPECT_NEAR(kp[4], 24 - fx.proj.f * 0.1 / 5, 1e-3);
  EXPECT_EQ(kp[5], 1);
  // Behind the camera, and on a missing limb: 0, 0, 0.
  for (std::size_t i = 6; i < 12; ++i) EXPECT_EQ(kp[i], 0) << i;
  EXPECT_EQ(a["num_keypoints"], 2);
  EXPECT_EQ(a["area"], 80);
  EXPECT_EQ(a["instance_id"], 1);
  EXPECT_EQ(a["motion_id"], "wave");
  EXPECT_EQ(a["category_id"], 1);
  // The box is the visible mask's.
  EXPECT_EQ(a["bbox"], nlohmann::ordered_json::array({28, 20, 10, 8}));
  // The amodal box holds the whole square; the visible fraction is mask over silhouette.
  const auto amodal = a["bbox_amodal"].get<std::vector<int>>();
  const double half = fx.proj.f * 1.0 / 5;  // the square's half width in pixels
  EXPECT_NEAR(amodal[0], 32 - half, 1.0);
  EXPECT_NEAR(amodal[2], 2 * half, 1.5);
  EXPECT_NEAR(a["visible_fraction"].get<double>(), 80.0 / (4 * half * half), 0.03);
  // Camera-space 3D keypoints; a missing one is zeros.
  const auto kp3 = a["keypoints_3d"].get<std::vector<double>>();
  EXPECT_EQ(kp3[2], -5.0);
  EXPECT_EQ(kp3[9], 0.0);
  ASSERT_TRUE(a.contains("segmentation"));
  EXPECT_EQ(a["segmentation"].size(), 1u);
}

TEST(Labeler, AVisibleKeypointOutsideTheMaskWidensTheBoxAndOptionsApply) {
  Fixture fx;
  fx.buffers.instance(cv::Rect(28, 20, 10, 8)).setTo(0);
  fx.buffers.instance(cv::Rect(40, 30, 10, 8)).setTo(1);  // the mask away from the centre
  LabelOptions options;
  options.segmentation = false;
  const FrameLabels labels = label_frame(fx.frame, fx.buffers, options);
  ASSERT_EQ(labels.annotations.size(), 1u);
  const nlohmann::ordered_json& a = labels.annotations[0];
  EXPECT_FALSE(a.contains("segmentation"));
  // With no depth in front both keypoints are visible, and the box reaches their pixels
  // (32, 24) and (33, 23).
  EXPECT_EQ(a["bbox"], nlohmann::ordered_json::array({32, 23, 18, 15}));
  options.min_visible_pixels = 81;
  EXPECT_EQ(label_frame(fx.frame, fx.buffers, options).dropped_people, 2);
}

TEST(Labeler, ABoxHoldingTheWheelchairSpansPersonAndChair) {
  Fixture fx;
  fx.buffers.instance(cv::Rect(26, 26, 14, 10)).setTo(kChairIdBase + 1);  // below and left
  fx.buffers.instance(cv::Rect(28, 20, 10, 6)).setTo(1);  // the chair covers the mask's foot
  const auto person_only = label_frame(fx.frame, fx.buffers, LabelOptions{}).annotations[0];
  EXPECT_EQ(person_only["bbox"], nlohmann::ordered_json::array({28, 20, 10, 6}));
  EXPECT_FALSE(person_only.contains("bbox_person"));
  LabelOptions options;
  options.box_holds_wheelchair = true;
  const auto held = label_frame(fx.frame, fx.buffers, options).annotations[0];
  EXPECT_EQ(held["bbox"], nlohmann::ordered_json::array({26, 20, 14, 16}));
  EXPECT_EQ(held["bbox_person"], person_only["bbox"]);
  EXPECT_EQ(held["area"], person_only["area"]);  // the person's own pixels
  // A person without a chair in sight keeps their own box.
  fx.buffers.instance.setTo(0, fx.buffers.instance == kChairIdBase + 1);
  const auto standing = label_frame(fx.frame, fx.buffers, options).annotations[0];
  EXPECT_EQ(standing["bbox"], person_only["bbox"]);
  EXPECT_FALSE(standing.contains("bbox_person"));
}

}  // namespace
}  // namespace wheelpose::generate
