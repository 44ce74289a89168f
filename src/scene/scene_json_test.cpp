#include "scene/scene_json.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/error.h"
#include "scene/primitives.h"

namespace wheelpose::scene {
namespace {

// A scene using every field with non-default values.
Scene full_scene() {
  Scene s;
  s.seed = 1234567890123ULL;
  s.meshes.push_back(make_sphere(0.7f, 6));
  Mesh tri;
  tri.name = "tri";
  tri.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0.1f}};
  tri.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  tri.uvs = {{0, 0}, {1, 0}, {0, 1.0f / 3.0f}};
  tri.triangles = {{0, 1, 2}};
  tri.motion = {{0.01f, 0, 0}, {0, -0.02f, 0}, {0, 0, 1.0f / 7.0f}};
  s.meshes.push_back(tri);
  Material m;
  m.name = "wood";
  m.diffuse = {0.1f, 0.2f, 0.3f};
  m.specular = 0.4f;
  m.shininess = 12.0f;
  m.hue_offset_deg = -33.3f;
  m.strands_per_uv = 150.0f;
  m.strand_coverage = 0.45f;
  m.texture.kind = TextureKind::kWood;
  m.texture.scale = 3.3f;
  m.texture.seed = 9;
  s.materials.push_back(m);
  Material img;
  img.texture.kind = TextureKind::kImage;
  img.texture.path = "tex/a.png";
  s.materials.push_back(img);
  Material detail;
  detail.diffuse = {0.5f, 0.1f, 0.1f};
  detail.texture.kind = TextureKind::kImageDetail;
  detail.texture.path = "/usr/share/x.sh3f!/fabrics/denim.jpg";
  detail.texture.scale = 2.5f;
  s.materials.push_back(detail);
  Instance in;
  in.name = "ball";
  in.mesh = 0;
  in.material = 1;
  in.transform.topRightCorner<3, 1>() = Eigen::Vector3f(0.1f, -2.0f, 3.7f);
  in.instance_id = 7;
  in.semantic_id = 65535;
  s.instances.push_back(in);
  s.sun.solar = SolarPosition{9.5f, 100.0f, 47.3f};
  s.sun.intensity = 2.5f;
  s.point_lights.push_back(PointLight{{1, 2, 3}, {0.5f, 0.6f, 0.7f}, 11.0f, 0.2f, false});
  s.environment = Environment{"sky.hdr", {0.1f, 0.2f, 0.3f}, 1.5f, 90.0f};
  s.camera.position = {1, 2, 3};
  s.camera.orientation =
      Eigen::Quaternionf(Eigen::AngleAxisf(0.3f, Eigen::Vector3f(1, 2, 3).normalized()));
  s.camera.focal_length_mm = 20.78f;
  s.camera.aperture_radius = 0.01f;
  s.camera.focus_distance = 4.0f;
  s.camera.width = 64;
  s.camera.height = 48;
  s.post =
      PostProcess{1.5f, -20, 30, -40, 0.5f, 0.3f, 0.9f, 0.7f, 3.0f, 0.2f, 0.004f, 0.001f, true};
  s.background.color = {0.3f, 0.2f, 0.1f};
  s.background.texture.kind = TextureKind::kChecker;
  s.background.image = "bg.jpg";
  return s;
}

TEST(SceneJson, RoundTripIsExact) {
  const Scene s = full_scene();
  const std::string text = dump_scene(s);
  const Scene back = parse_scene(text, "<test>");
  EXPECT_TRUE(back == s);
  EXPECT_EQ(dump_scene(back), text);
}

TEST(SceneJson, DefaultSceneRoundTrips) {
  const Scene s;
  EXPECT_TRUE(parse_scene(dump_scene(s), "<test>") == s);
  EXPECT_EQ(parse_scene("{}", "<test>").camera.width, 1280);
  EXPECT_EQ(parse_scene("{}", "<test>").camera.height, 720);
}

TEST(SceneJson, PrimitiveMeshIsDumpedAsItsSpec) {
  Scene s;
  s.meshes.push_back(make_box(Eigen::Vector3f(1, 2, 3), 2));
  const auto j = scene_to_json(s);
  EXPECT_EQ(j["meshes"][0]["primitive"]["type"], "box");
  EXPECT_FALSE(j["meshes"][0].contains("positions"));
  EXPECT_EQ(parse_scene(j.dump(), "x").meshes[0].positions.size(), 6u * 9u);
}

TEST(SceneJson, LookAtPointsTheCameraMinusZAtTheTarget) {
  const Scene s = parse_scene(R"({"camera": {"position": [0, 0, 5], "look_at": [5, 0, 5]}})", "x");
  const Eigen::Vector3f forward = s.camera.orientation * Eigen::Vector3f(0, 0, -1);
  EXPECT_NEAR(forward.x(), 1.0f, 1e-6f);
  EXPECT_NEAR((s.camera.orientation * Eigen::Vector3f(0, 1, 0)).y(), 1.0f, 1e-6f);
}

TEST(SceneJson, TranslationRotationScaleBuildTheTransform) {
  const Scene s = parse_scene(R"({"meshes": [{"primitive": {"type": "sphere"}}],
      "materials": [{}], "instances": [{"mesh": 0, "translation": [1, 2, 3],
      "rotation_deg": [0, 90, 0], "scale": [2, 2, 2]}]})",
                              "x");
  const Eigen::Vector4f p = s.instances[0].transform * Eigen::Vector4f(1, 0, 0, 1);
  EXPECT_NEAR(p.x(), 1.0f, 1e-5f);  // +X rotated 90° about Y is −Z, times 2, plus translation
  EXPECT_NEAR(p.z(), 1.0f, 1e-5f);
}

TEST(SceneJson, FocalLengthOverridesFov) {
  Camera c;
  c.vfov_deg = 30;
  EXPECT_NEAR(c.effective_vfov(), 30.0f * 3.14159265f / 180.0f, 1e-6f);
  c.focal_length_mm = 12.0f;
  c.sensor_height_mm = 24.0f;
  EXPECT_NEAR(c.effective_vfov(), 2.0f * std::atan(1.0f), 1e-6f);  // 90°
}

void expect_error(const std::string& text, const std::string& needle) {
  try {
    parse_scene(text, "s.json");
    FAIL() << "no error for " << text;
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << "one line: " << e.what();
    EXPECT_EQ(std::string(e.what()).rfind("s.json: ", 0), 0u) << e.what();
  }
}

TEST(SceneJson, BadInputNamesFileAndPath) {
  expect_error("{\"camera\": {", "malformed JSON");
  expect_error(R"({"camera": {"width": 0}})", "/camera/width: must be in 1..16384");
  expect_error(R"({"camera": {"widht": 10}})", "/camera/widht: unknown key");
  expect_error(R"({"materials": [{}, {"texture": {"kind": "plaid"}}]})",
               "/materials/1/texture/kind: unknown texture kind 'plaid'");
  expect_error(R"({"materials": [{"diffuse": [1, 2]}]})",
               "/materials/0/diffuse: expected an array of 3");
  expect_error(R"({"meshes": [{"positions": [[0,0,0]], "triangles": [[0, 1, 0]]}]})",
               "/meshes/0/triangles/0/1: vertex index out of range");
  expect_error(
      R"({"meshes": [{"positions": [[0,0,0]], "triangles": [], "motion": [[0,0,0], [1,0,0]]}]})",
      "/meshes/0/motion: needs one motion vector per position");
  expect_error(R"({"meshes": [{"primitive": {"type": "torus"}}]})",
               "/meshes/0/primitive: unknown primitive");
  expect_error(R"({"meshes": [], "materials": [{}], "instances": [{"mesh": 0}]})",
               "/instances/0/mesh: must be in 0..-1");
  expect_error(R"({"materials": [{"strands_per_uv": 100, "strand_coverage": 0}]})",
               "/materials/0/strand_coverage: must be in 0.05 .. 1");
  expect_error(R"({"post": {"vignette": 2}})", "/post/vignette: must be in 0 .. 1");
  expect_error(R"({"post": {"shot_noise": -1}})", "/post/shot_noise: must be in 0 .. 1");
  expect_error(R"({"sun": {"direction": [0, 0, 0]}})",
               "/sun/direction: direction must not be zero");
  expect_error(R"([1, 2])", "s.json: /: expected an object");
}

TEST(SceneJson, LoadResolvesPathsAndRequiresFiles) {
  const auto dir = std::filesystem::temp_directory_path() / "wheelpose_scene_json_test";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const auto file = dir / "s.json";
  std::ofstream(file) << R"({"materials": [{"texture": {"kind": "image", "path": "t.png"}}]})";
  try {
    load_scene(file);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("/materials/0/texture/path: file"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("t.png' not found"), std::string::npos);
  }
  std::ofstream(dir / "t.png") << "x";
  const Scene s = load_scene(file);
  EXPECT_EQ(resolve_path(s, "t.png"), (dir / "t.png").string());
  std::filesystem::remove_all(dir);
}

TEST(Solar, NoonAtTheEquatorOnAnEquinoxIsOverhead) {
  // Day 80 ≈ March equinox: declination ≈ 0.
  const Eigen::Vector3f d = solar_direction({12.0f, 80.0f, 0.0f});
  EXPECT_GT(d.y(), 0.999f);
}

TEST(Solar, MorningSunIsInTheEastAndMidnightBelowTheHorizon) {
  const Eigen::Vector3f morning = solar_direction({8.0f, 172.0f, 45.0f});
  EXPECT_GT(morning.x(), 0.5f);
  EXPECT_GT(morning.y(), 0.0f);
  EXPECT_LT(solar_direction({0.0f, 172.0f, 45.0f}).y(), 0.0f);
}

TEST(Solar, NorthernSummerNoonElevationMatchesTheTextbook) {
  // Latitude 50° N, June solstice (δ = +23.44°): elevation = 90 − 50 + 23.44 = 63.44°, due south.
  const Eigen::Vector3f d = solar_direction({12.0f, 172.0f, 50.0f});
  EXPECT_NEAR(std::asin(d.y()) * 180.0f / 3.14159265f, 63.44f, 0.05f);
  EXPECT_NEAR(d.x(), 0.0f, 1e-5f);
  EXPECT_GT(d.z(), 0.0f);  // south = +Z
}

TEST(Primitives, NormalsAreUnitAndOutward) {
  for (const Mesh& m :
       {make_sphere(2, 8), make_box({1, 2, 3}, 2), make_capsule(0.5f, 1, 8), make_plane(1, 1, 3)}) {
    ASSERT_EQ(m.normals.size(), m.positions.size());
    for (std::size_t i = 0; i < m.normals.size(); ++i) {
      EXPECT_NEAR(m.normals[i].norm(), 1.0f, 1e-5f);
      if (m.primitive->type != "plane") {
        EXPECT_GT(m.normals[i].dot(m.positions[i]), 0.0f);
      }
    }
    for (const auto& t : m.triangles) {
      const Eigen::Vector3f face =
          (m.positions[t[1]] - m.positions[t[0]]).cross(m.positions[t[2]] - m.positions[t[0]]);
      EXPECT_GT(face.dot(m.normals[t[0]] + m.normals[t[1]] + m.normals[t[2]]), 0.0f);
    }
  }
}

}  // namespace
}  // namespace wheelpose::scene
