#include "body/rigged_fbx.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <map>
#include <string>

#include "body/test_data.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "motion/fbx_binary.h"
#include "motion/fbx_scene.h"
#include "motion/fbx_test_reader.h"
#include "motion/fbx_test_scene.h"
#include "motion/fbx_time.h"
#include "motion/library.h"
#include "motion/pipeline.h"

namespace wheelpose::body {
namespace {

namespace fbx = motion::fbx;
using fbx::Node;
using fbx::testing::child;
using fbx::testing::FbxScene;
using fbx::testing::matrix_of;
using fbx::testing::name_of;
using fbx::testing::property;
using fbx::testing::value;
using testing::body_data;
using testing::max_distance;
using testing::mean_distance;
namespace fs = std::filesystem;

const motion::SkeletalMotion& test_clip() {
  static const motion::SkeletalMotion clip =
      motion::run_motion_pipeline(motion::library_clip("basketball_chest_pass", 3), {}).motion;
  return clip;
}

std::int64_t id_of(const Node& object) { return value<std::int64_t>(object); }

// The Geometry named `name`, or nullptr.
const Node* geometry(const FbxScene& scene, const std::string& name) {
  for (const Node* g : scene.of_type("Geometry"))
    if (name_of(*g) == name) return g;
  return nullptr;
}

// The geometry's vertices as a reader skins them at `tick`: each cluster's bone world matrix
// times its Transform, blended by the cluster weights. Unskinned geometry follows its model.
std::vector<Eigen::Vector3f> skinned(const FbxScene& scene, const Node& geometry, std::int64_t tick,
                                     std::vector<double>* weight_sums = nullptr) {
  const auto world = fbx::testing::world_transforms(scene, tick);
  const auto& xyz = value<std::vector<double>>(child(geometry, "Vertices"));
  std::vector<Eigen::Vector3d> rest(xyz.size() / 3);
  for (std::size_t v = 0; v < rest.size(); ++v)
    rest[v] = {xyz[3 * v], xyz[3 * v + 1], xyz[3 * v + 2]};
  std::vector<Eigen::Vector3d> out(rest.size(), Eigen::Vector3d::Zero());
  std::vector<double> sums(rest.size(), 0.0);
  const auto skins = scene.children_of(id_of(geometry), "Deformer");
  if (skins.empty()) {
    const Eigen::Isometry3d& model = world.at(scene.parent_of(id_of(geometry)));
    for (std::size_t v = 0; v < rest.size(); ++v) out[v] = model * rest[v];
  }
  for (const auto& [skin, unused] : skins) {
    for (const auto& [cluster, link] : scene.children_of(id_of(*skin), "Deformer")) {
      const auto bones = scene.children_of(id_of(*cluster), "Model");
      EXPECT_EQ(bones.size(), 1u);
      const Eigen::Affine3d m =
          world.at(id_of(*bones[0].first)) * matrix_of(child(*cluster, "Transform"));
      const auto& indexes = value<std::vector<std::int32_t>>(child(*cluster, "Indexes"));
      const auto& weights = value<std::vector<double>>(child(*cluster, "Weights"));
      EXPECT_EQ(indexes.size(), weights.size());
      for (std::size_t i = 0; i < indexes.size(); ++i) {
        const auto v = static_cast<std::size_t>(indexes[i]);
        out[v] += weights[i] * (m * rest[v]);
        sums[v] += weights[i];
      }
    }
  }
  if (weight_sums) *weight_sums = sums;
  std::vector<Eigen::Vector3f> result;
  for (const auto& p : out) result.push_back(p.cast<float>());
  return result;
}

TEST(RiggedFbx, PlaysBackAsBuildPersonPosesThePerson) {
  const motion::SkeletalMotion& clip = test_clip();
  PersonSpec spec = sample_spec(5);
  spec.limbs = {};
  spec.proxies = {"clothes/male_casualsuit01", "clothes/shoes01", "hair/bob01"};
  const PersonAnimation animation = animate_person(body_data(), spec, clip);
  const std::vector<Node> document = rigged_person_fbx_document(animation, body_data());
  // The file is the document, byte for byte readable back.
  const fs::path path = fs::temp_directory_path() / "wheelpose_rigged_fbx_test.fbx";
  write_rigged_person_fbx(animation, body_data(), path);
  const std::string bytes = read_file(path);
  EXPECT_TRUE(fbx::testing::read_binary(bytes) == document);
  write_rigged_person_fbx(animation, body_data(), path);
  EXPECT_TRUE(read_file(path) == bytes);  // same input, same bytes

  const FbxScene scene(document);
  std::size_t bones = 0;
  for (const Node* model : scene.of_type("Model"))
    bones += value<std::string>(*model, 2) == "LimbNode";
  EXPECT_EQ(bones, body_data().rig().bones.size());
  ASSERT_EQ(scene.of_type("AnimationStack").size(), 1u);
  for (const Node* curve : scene.of_type("AnimationCurve")) {
    ASSERT_EQ(value<std::vector<std::int64_t>>(child(*curve, "KeyTime")).size(),
              clip.frame_count());
  }
  const Node* body = geometry(scene, "body");
  ASSERT_NE(body, nullptr);
  // The body's colour is the skin colour the renderer uses.
  const auto materials = scene.children_of(scene.parent_of(id_of(*body)), "Material");
  ASSERT_EQ(materials.size(), 1u);
  const Node& diffuse = property(child(*materials[0].first, "Properties70"), "DiffuseColor");
  EXPECT_NEAR(value<double>(diffuse, 4), animation.person.skin.x(), 1e-6);

  const motion::FrameRate rate = motion::exact_frame_rate(clip.fps);
  float worst_body = 0, worst_garment = 0, worst_garment_mean = 0;
  for (std::size_t frame : {std::size_t{0}, clip.frame_count() / 2, clip.frame_count() - 1}) {
    const std::int64_t tick = motion::fbx_frame_time(static_cast<std::int64_t>(frame), rate);
    PersonSpec at_frame = spec;
    at_frame.pose = motion::global_rotations(clip, frame);
    const Person expected = build_person(body_data(), at_frame);
    std::vector<double> sums;
    worst_body =
        std::max(worst_body, max_distance(skinned(scene, *body, tick, &sums), expected.vertices));
    for (double s : sums) ASSERT_NEAR(s, 1.0, 1e-6);
    for (const Garment& g : expected.garments) {
      const Node* mesh = geometry(scene, g.name.substr(g.name.find('/') + 1));
      ASSERT_NE(mesh, nullptr) << g.name;
      const std::vector<Eigen::Vector3f> moved = skinned(scene, *mesh, tick);
      worst_garment = std::max(worst_garment, max_distance(moved, g.vertices));
      worst_garment_mean = std::max(worst_garment_mean, mean_distance(moved, g.vertices));
    }
  }
  std::printf("rigged fbx vs build_person: body %.4f mm, garments mean %.1f mm, worst %.1f mm\n",
              worst_body * 1e3, worst_garment_mean * 1e3, worst_garment * 1e3);
  EXPECT_LT(worst_body, 0.001f);
  // As in the glb (rigged_glb_test.cpp): garments are refitted per pose by build_person.
  EXPECT_LT(worst_garment_mean, 0.01f);
  EXPECT_LT(worst_garment, 0.05f);
}

TEST(RiggedFbx, ChairStaysUnskinnedAndCaneFollowsTheHand) {
  const motion::SkeletalMotion& clip = test_clip();
  PersonSpec spec = sample_spec(11);
  spec.wheelchair = WheelchairType::kManual;
  spec.mobility_aid = MobilityAidType::kCane;
  const PersonAnimation animation = animate_person(body_data(), spec, clip);
  const FbxScene scene(rigged_person_fbx_document(animation, body_data()));
  std::int64_t root = 0;
  for (const Node* model : scene.of_type("Model"))
    if (name_of(*model) == "wheelpose_person") root = id_of(*model);
  ASSERT_NE(root, 0);
  std::size_t chair_meshes = 0;
  for (const Node* g : scene.of_type("Geometry")) {
    if (name_of(*g).rfind("wheelchair", 0) != 0) continue;
    ++chair_meshes;
    EXPECT_TRUE(scene.children_of(id_of(*g), "Deformer").empty()) << name_of(*g);
    EXPECT_EQ(scene.parent_of(scene.parent_of(id_of(*g))), root) << name_of(*g);
  }
  EXPECT_GT(chair_meshes, 0u);
  // The cane's grip stays as near the wrist at the last frame as at the first.
  const Node* grip = geometry(scene, "mobility_aid_hand_r_grips");
  ASSERT_NE(grip, nullptr);
  const std::size_t last = clip.frame_count() - 1;
  PersonSpec at_last = spec;
  at_last.pose = motion::global_rotations(clip, last);
  const Person expected = build_person(body_data(), at_last);
  auto nearest = [](const std::vector<Eigen::Vector3f>& points, const Eigen::Vector3f& to) {
    float best = 1e9f;
    for (const auto& p : points) best = std::min(best, (p - to).norm());
    return best;
  };
  const motion::FrameRate rate = motion::exact_frame_rate(clip.fps);
  const float at_start = nearest(skinned(scene, *grip, 0), animation.person.coco[10]);
  const float at_end =
      nearest(skinned(scene, *grip, motion::fbx_frame_time(static_cast<std::int64_t>(last), rate)),
              expected.coco[10]);
  EXPECT_NEAR(at_end, at_start, 0.01f);
}

TEST(RiggedFbx, NamesFbxCannotHoldAreBadInputAndNoFile) {
  PersonAnimation animation = animate_person(body_data(), sample_spec(2), test_clip());
  animation.name = "Model::clip";
  const fs::path path = fs::temp_directory_path() / "wheelpose_rigged_fbx_bad.fbx";
  fs::remove(path);
  try {
    write_rigged_person_fbx(animation, body_data(), path);
    ADD_FAILURE() << "written";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::kBadInput);
    EXPECT_NE(std::string(e.what()).find("contains '::'"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(path));
}

}  // namespace
}  // namespace wheelpose::body
