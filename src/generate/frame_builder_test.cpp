#include "generate/frame_builder.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"
#include "motion/library.h"
#include "motion/pipeline.h"

namespace wheelpose::generate {
namespace {

using Eigen::Vector3f;

const body::BodyData& body_data() {
  static const body::BodyData data(std::filesystem::path(WHEELPOSE_SHARED_DIR) / "assets");
  return data;
}

// Two seated people (the second with a cane and chosen chair colours), an empty chair and an
// occluder in a room.
FrameDraft room_draft() {
  FrameDraft draft;
  draft.index = 3;
  draft.seed = 5;
  draft.environment = EnvironmentKind::kRoom;
  for (int k = 0; k < 2; ++k) {
    PersonDraft p;
    p.spec = body::sample_spec(20 + k);
    p.spec.wheelchair = body::WheelchairType::kManual;
    p.outfit.top.diffuse = Vector3f(0.9f, 0.1f, 0.1f);
    p.position = Vector3f(k == 0 ? -1.0f : 1.0f, 0.0f, -4.0f);
    p.rotation = Eigen::Quaternionf(Eigen::AngleAxisf(0.5f * k, Vector3f::UnitY()));
    p.scale = k == 0 ? 1.0f : 0.9f;
    draft.people.push_back(p);
  }
  draft.people[1].spec.mobility_aid = body::MobilityAidType::kCane;
  draft.people[1].chair_colours = std::array<Vector3f, 4>{
      Vector3f(0.1f, 0.2f, 0.3f), Vector3f(0.4f, 0.5f, 0.6f), Vector3f(0, 0, 0), Vector3f(1, 1, 1)};
  draft.empty_chairs.push_back(
      {body::WheelchairType::kSport, 9, Vector3f(0, 0, -6), Eigen::Quaternionf::Identity(), 1.0f,
       std::array<Vector3f, 4>{Vector3f(0.7f, 0.1f, 0.2f), Vector3f(0.01f, 0.02f, 0.03f),
                               Vector3f(0.05f, 0.05f, 0.05f), Vector3f(0.6f, 0.6f, 0.6f)}});
  ObjectDraft box;
  box.position = Vector3f(2, 0, -5);
  draft.objects.push_back(box);
  return draft;
}

TEST(FrameBuilder, InstancesFollowTheIdSchemeAndPartsWearTheirMaterials) {
  const std::vector<KeypointAnchor> anchors = resolve_anchors(load_keypoint_template("coco17"));
  const BuiltFrame built = build_frame(room_draft(), body_data(), {}, anchors);
  const scene::Scene& s = built.scene;
  int person_parts = 0, aid_parts = 0, skin_parts = 0, empty_frame = 0, empty_seat = 0;
  for (const scene::Instance& inst : s.instances) {
    const std::string& n = inst.name;
    const scene::Material& m = s.materials[static_cast<std::size_t>(inst.material)];
    EXPECT_EQ(m.name, n);
    if (n.starts_with("person_2_wheelchair_")) {
      EXPECT_EQ(inst.instance_id, kChairIdBase + 2) << n;
      EXPECT_EQ(inst.semantic_id, kSemanticWheelchair) << n;
      if (n == "person_2_wheelchair_frame") {
        EXPECT_EQ(m.diffuse, Vector3f(0.1f, 0.2f, 0.3f));
      }
    } else if (n.starts_with("person_2_mobility_aid_")) {
      ++aid_parts;
      EXPECT_EQ(inst.instance_id, kAidIdBase + 2) << n;
      EXPECT_EQ(inst.semantic_id, kSemanticMobilityAid) << n;
    } else if (n.starts_with("person_1_wheelchair_")) {
      EXPECT_EQ(inst.instance_id, kChairIdBase + 1) << n;
    } else if (n.starts_with("person_")) {
      ++person_parts;
      EXPECT_EQ(inst.instance_id, n[7] == '1' ? 1 : 2) << n;
      EXPECT_EQ(inst.semantic_id, kSemanticPerson) << n;
      if (n == "person_1_top") {
        EXPECT_EQ(m.diffuse, Vector3f(0.9f, 0.1f, 0.1f));
      }
      if (n == "person_1_skin") {  // a faint mottle about the skin colour, redder at one end
        ++skin_parts;
        EXPECT_EQ(m.texture.kind, scene::TextureKind::kNoise);
        const Vector3f ratio = m.texture.color_a.cwiseQuotient(m.texture.color_b);
        EXPECT_GT(ratio.x(), ratio.z());
        EXPECT_GT(ratio.minCoeff(), 1.0f);
        EXPECT_LT(ratio.maxCoeff(), 1.2f);
      }
    } else if (n.starts_with("empty_wheelchair_1_")) {
      EXPECT_EQ(inst.instance_id, kEmptyChairIdBase + 1) << n;
      EXPECT_EQ(inst.semantic_id, kSemanticWheelchair) << n;
      // The empty chair wears its drawn colours.
      empty_frame += m.diffuse == Vector3f(0.7f, 0.1f, 0.2f);
      empty_seat += m.diffuse == Vector3f(0.01f, 0.02f, 0.03f);
    } else if (n == "object_1") {
      EXPECT_EQ(inst.instance_id, kObjectIdBase + 1);
      EXPECT_EQ(inst.semantic_id, kSemanticObject);
    } else {
      EXPECT_GT(inst.instance_id, kStructureIdBase) << n;
      EXPECT_EQ(inst.semantic_id, kSemanticStructure) << n;
    }
  }
  EXPECT_GE(person_parts, 4);  // at least skin and top for each person
  EXPECT_EQ(skin_parts, 1);
  EXPECT_GE(aid_parts, 1);
  EXPECT_GE(empty_frame, 1);
  EXPECT_GE(empty_seat, 1);
  // Floor, ceiling and four walls.
  EXPECT_EQ(
      std::count_if(s.instances.begin(), s.instances.end(),
                    [](const scene::Instance& i) { return i.semantic_id == kSemanticStructure; }),
      6);
}

TEST(FrameBuilder, PeopleAreLabelledWhereTheyArePlacedWithTheirWheelsOnTheFloor) {
  const std::vector<KeypointAnchor> anchors = resolve_anchors(load_keypoint_template("coco17"));
  const FrameDraft draft = room_draft();
  const BuiltFrame built = build_frame(draft, body_data(), {}, anchors);
  ASSERT_EQ(built.people.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    const LabelPerson& label = built.people[k];
    EXPECT_EQ(label.instance_id, k + 1);
    ASSERT_EQ(label.keypoints.size(), 17u);
    ASSERT_EQ(label.present.size(), 17u);
    EXPECT_FLOAT_EQ(label.tolerance[0], anchors[0].tolerance_m * draft.people[k].scale);
    // In a room the pelvis stands over `position` (x, z): the hips straddle it.
    const Vector3f hips = 0.5f * (label.keypoints[11] + label.keypoints[12]);
    const Vector3f off = hips - draft.people[k].position;
    EXPECT_LT(std::hypot(off.x(), off.z()), 0.15f) << k;
    EXPECT_EQ(label.attributes["motion_id"], "rest_seated");
    EXPECT_EQ(label.attributes["wheelchair_type"], "manual");
  }
  EXPECT_EQ(built.people[1].attributes["mobility_aid"], "cane");
  // The chair's wheels touch the floor (y = 0) at any scale.
  int tyres = 0;
  for (const scene::Instance& inst : built.scene.instances) {
    if (!inst.name.starts_with("person_2_wheelchair_tyre")) continue;
    ++tyres;
    float lowest = 1e9f;
    for (const Vector3f& p : built.scene.meshes[static_cast<std::size_t>(inst.mesh)].positions) {
      lowest = std::min(lowest, p.y());
    }
    EXPECT_NEAR(lowest, 0.0f, 0.005f);
  }
  EXPECT_EQ(tyres, 1);
}

// In a room, an object the camera stands in or beside (within 0.3 m of its box) is left out;
// the others keep their ids.
TEST(FrameBuilder, ObjectsAroundTheRoomCameraAreLeftOut) {
  FrameDraft draft = room_draft();
  draft.camera.position = Vector3f(-2, 1.2f, 3);
  ObjectDraft around_camera;
  around_camera.position = Vector3f(-2, 0, 3.4f);  // a 1 m box 0.2 m below the camera
  draft.objects.push_back(around_camera);
  const auto object_names = [](const BuiltFrame& built) {
    std::vector<std::string> names;
    for (const scene::Instance& inst : built.scene.instances) {
      if (inst.name.starts_with("object_")) names.push_back(inst.name);
    }
    return names;
  };
  EXPECT_EQ(object_names(build_frame(draft, body_data(), {}, {})),
            std::vector<std::string>{"object_1"});
  draft.objects.back().position = Vector3f(-2, 0, 4.0f);  // 0.54 m away: kept
  EXPECT_EQ(object_names(build_frame(draft, body_data(), {}, {})),
            (std::vector<std::string>{"object_1", "object_2"}));
}

// Framing moves the camera without a rebuild when the other camera leaves out the same objects:
// the frame built for one camera with the other put in is the frame built for the other.
TEST(FrameBuilder, ACameraThatLeavesOutTheSameObjectsNeedsNoRebuild) {
  FrameDraft draft = room_draft();
  draft.camera.position = Vector3f(-2, 1.2f, 3);
  ObjectDraft around_camera;
  around_camera.position = Vector3f(-2, 0, 3.4f);  // left out from the first camera only
  draft.objects.push_back(around_camera);
  const BuiltFrame first = build_frame(draft, body_data(), {}, {});
  ASSERT_EQ(first.room_object_boxes.size(), draft.objects.size());

  FrameDraft moved = draft;
  moved.camera.position = Vector3f(-2.1f, 1.3f, 3.1f);  // still beside the same box
  EXPECT_TRUE(leaves_out_the_same_objects(first, draft.camera.position, moved.camera.position));
  BuiltFrame reused = first;
  reused.scene.camera = moved.camera;
  EXPECT_TRUE(reused.scene == build_frame(moved, body_data(), {}, {}).scene);

  moved.camera.position = Vector3f(2, 1.2f, 3);  // the box is kept from here
  EXPECT_FALSE(leaves_out_the_same_objects(first, draft.camera.position, moved.camera.position));
  EXPECT_FALSE(reused.scene == build_frame(moved, body_data(), {}, {}).scene);
}

// Outdoors the room's layout stands on open ground: one ground plane to the horizon, no walls
// or ceiling, the furniture on it as in a room.
TEST(FrameBuilder, OutdoorFramesHaveGroundAndNoWalls) {
  FrameDraft draft = room_draft();
  draft.objects.emplace_back();
  const auto structure = [](const BuiltFrame& built) {
    std::vector<std::string> names;
    for (const scene::Instance& inst : built.scene.instances) {
      const std::string& n = inst.name;
      if (n == "floor" || n == "ceiling" || n == "ground" || n.starts_with("wall_"))
        names.push_back(n);
    }
    return names;
  };
  const BuiltFrame room = build_frame(draft, body_data(), {}, {});
  EXPECT_EQ(structure(room), (std::vector<std::string>{"floor", "ceiling", "wall_back",
                                                       "wall_front", "wall_left", "wall_right"}));
  draft.room.outdoor = true;
  const BuiltFrame outdoor = build_frame(draft, body_data(), {}, {});
  ASSERT_EQ(structure(outdoor), std::vector<std::string>{"ground"});
  const scene::Instance& ground_instance =
      *std::find_if(outdoor.scene.instances.begin(), outdoor.scene.instances.end(),
                    [](const scene::Instance& inst) { return inst.name == "ground"; });
  const scene::Mesh& ground = outdoor.scene.meshes[ground_instance.mesh];
  float far = 0;
  for (const Vector3f& p : ground.positions) far = std::max(far, p.cwiseAbs().maxCoeff());
  EXPECT_EQ(far, kOutdoorGroundSize / 2);
  EXPECT_EQ(outdoor.scene.instances.size(), room.scene.instances.size() - 5);
}

// A statue is a posed body in one material, labelled as an object: the people to label stay
// the frame's people.
TEST(FrameBuilder, StatuesAreObjectsOfOneMaterial) {
  FrameDraft draft = room_draft();
  const BuiltFrame without = build_frame(draft, body_data(), {}, {});
  StatueDraft statue;
  statue.spec = body::sample_spec(7);
  statue.spec.wheelchair = body::WheelchairType::kNone;
  statue.position = Vector3f(2.5f, 0, -5);
  statue.material.diffuse = Vector3f(0.15f, 0.1f, 0.05f);
  draft.statues.push_back(statue);
  const BuiltFrame with = build_frame(draft, body_data(), {}, {});
  EXPECT_EQ(with.people.size(), without.people.size());
  int parts = 0;
  float lowest = 1e9f;
  for (const scene::Instance& inst : with.scene.instances) {
    if (!inst.name.starts_with("statue_1_")) continue;
    ++parts;
    EXPECT_EQ(inst.instance_id, kStatueIdBase + 1);
    EXPECT_EQ(inst.semantic_id, kSemanticObject);
    EXPECT_EQ(with.scene.materials[inst.material].diffuse, statue.material.diffuse) << inst.name;
    for (const Vector3f& p : with.scene.meshes[inst.mesh].positions)
      lowest = std::min(lowest, p.y());
  }
  EXPECT_GT(parts, 0);
  EXPECT_NEAR(lowest, 0.0f, 0.05f);  // standing on the floor
  EXPECT_EQ(with.scene.instances.size(), without.scene.instances.size() + parts);
}

TEST(FrameBuilder, AnOpenShutterMovesPeopleAlongTheirClipAndKeepsTheLabels) {
  const std::vector<motion::SeatedClip> clips = {
      motion::run_motion_pipeline(motion::library_clip("clap_hands", 1), {})};
  const std::vector<KeypointAnchor> anchors = resolve_anchors(load_keypoint_template("coco17"));
  const double fps = clips[0].motion.fps;
  FrameDraft draft = room_draft();
  draft.people[0].clip = 0;
  draft.people[0].time = 30.3 / fps;  // frame 30
  const BuiltFrame instant = build_frame(draft, body_data(), clips, anchors);
  draft.shutter = 0.02f;
  const BuiltFrame open = build_frame(draft, body_data(), clips, anchors);
  draft.shutter = 0;
  draft.people[0].time = 31.3 / fps;  // frame 31
  const BuiltFrame next = build_frame(draft, body_data(), clips, anchors);

  // Labels and geometry are those of the instant: only the streaks are new.
  ASSERT_EQ(open.people.size(), instant.people.size());
  for (std::size_t k = 0; k < open.people.size(); ++k)
    EXPECT_EQ(open.people[k].keypoints, instant.people[k].keypoints);
  ASSERT_EQ(open.scene.meshes.size(), instant.scene.meshes.size());
  // Each wrist's nearest skin vertex travels about as the wrist does from frame 30 to 31,
  // scaled to the shutter (a vertex a few centimetres from the joint turns with the hand).
  const scene::Mesh* skin = nullptr;
  for (std::size_t i = 0; i < open.scene.meshes.size(); ++i) {
    const scene::Mesh& mesh = open.scene.meshes[i];
    EXPECT_EQ(mesh.positions, instant.scene.meshes[i].positions) << mesh.name;
    if (mesh.name == "person_1_skin") skin = &mesh;
    if (!mesh.name.starts_with("person_1_")) {
      EXPECT_TRUE(mesh.motion.empty()) << mesh.name;
    }
  }
  ASSERT_NE(skin, nullptr);
  ASSERT_EQ(skin->motion.size(), skin->positions.size());
  for (const int wrist : {9, 10}) {
    const Vector3f joint = instant.people[0].keypoints[wrist];
    const Vector3f travel =
        (next.people[0].keypoints[wrist] - joint) * static_cast<float>(0.02 * fps);
    std::size_t nearest = 0;
    for (std::size_t v = 1; v < skin->positions.size(); ++v) {
      if ((skin->positions[v] - joint).norm() < (skin->positions[nearest] - joint).norm())
        nearest = v;
    }
    EXPECT_GT(travel.norm(), 0.002f) << "the clip's wrist " << wrist << " should move";
    EXPECT_LT((skin->motion[nearest] - travel).norm(), 0.3f * travel.norm() + 0.002f)
        << "wrist " << wrist << ": " << skin->motion[nearest].transpose() << " against "
        << travel.transpose();
  }
}

TEST(FrameBuilder, RefusesTooManyPeopleAndUnknownAnchors) {
  FrameDraft draft;
  draft.index = 12;
  draft.people.resize(kMaxPeoplePerFrame + 1);
  try {
    build_frame(draft, body_data(), {}, {});
    FAIL() << "accepted 1000 people";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("frame 12"), std::string::npos) << e.what();
  }
  KeypointTemplate bad = load_keypoint_template("coco17");
  bad.keypoints[3].anchor = "joint:left_antenna";
  try {
    resolve_anchors(bad);
    FAIL() << "accepted an unknown anchor";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("joint:left_antenna"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace wheelpose::generate
