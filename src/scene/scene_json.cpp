#include "scene/scene_json.h"

#include <array>
#include <cmath>
#include <filesystem>
#include <initializer_list>
#include <limits>
#include <numbers>
#include <set>

#include "core/archive_member.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "scene/primitives.h"

namespace wheelpose::scene {
namespace {

using nlohmann::json;

constexpr std::array<const char*, 9> kTextureKinds = {
    "none", "image", "noise", "stripes", "checker", "fabric", "wood", "marble", "image_detail"};

// Reads one JSON object with a path for error messages and a list of the keys it allows.
class Reader {
 public:
  Reader(const json& j, std::string origin, std::string path)
      : j_(j), origin_(std::move(origin)), path_(std::move(path)) {
    if (!j_.is_object()) fail("expected an object");
  }

  [[noreturn]] void fail(const std::string& what) const { fail_at(path_, what); }
  [[noreturn]] void fail_at(const std::string& path, const std::string& what) const {
    throw Error(origin_ + ": " + (path.empty() ? "/" : path) + ": " + what);
  }
  std::string at(const std::string& key) const { return path_ + "/" + key; }

  // Unknown keys are errors: a typo must not silently fall back to a default.
  void allow(std::initializer_list<const char*> keys) const {
    const std::set<std::string> allowed(keys.begin(), keys.end());
    for (const auto& [key, value] : j_.items()) {
      if (!allowed.contains(key)) fail_at(at(key), "unknown key");
    }
  }
  bool has(const char* key) const { return j_.contains(key); }
  const json& raw(const char* key) const { return j_.at(key); }
  Reader child(const char* key) const { return Reader(j_.at(key), origin_, at(key)); }
  const std::string& origin() const { return origin_; }

  void read(const char* key, float& out) const {
    if (!has(key)) return;
    const json& v = j_.at(key);
    if (!v.is_number()) fail_at(at(key), "expected a number");
    const double d = v.get<double>();
    if (!std::isfinite(d)) fail_at(at(key), "expected a finite number");
    out = static_cast<float>(d);
  }
  void read(const char* key, int& out, int lo, int hi) const {
    if (!has(key)) return;
    const json& v = j_.at(key);
    if (!v.is_number_integer()) fail_at(at(key), "expected an integer");
    const auto i = v.get<std::int64_t>();
    if (i < lo || i > hi) {
      fail_at(at(key), "must be in " + std::to_string(lo) + ".." + std::to_string(hi));
    }
    out = static_cast<int>(i);
  }
  void read(const char* key, std::uint64_t& out) const {
    if (!has(key)) return;
    const json& v = j_.at(key);
    if (!v.is_number_unsigned()) fail_at(at(key), "expected a non-negative integer");
    out = v.get<std::uint64_t>();
  }
  void read(const char* key, bool& out) const {
    if (!has(key)) return;
    if (!j_.at(key).is_boolean()) fail_at(at(key), "expected true or false");
    out = j_.at(key).get<bool>();
  }
  void read(const char* key, std::string& out) const {
    if (!has(key)) return;
    if (!j_.at(key).is_string()) fail_at(at(key), "expected a string");
    out = j_.at(key).get<std::string>();
  }
  template <int N>
  void read(const char* key, Eigen::Matrix<float, N, 1>& out) const {
    if (!has(key)) return;
    out = vec<N>(j_.at(key), at(key));
  }
  void read_range(const char* key, float& out, float lo, float hi) const {
    read(key, out);
    if (out < lo || out > hi) {
      fail_at(at(key), "must be in " + fmt(lo) + " .. " + fmt(hi));
    }
  }

  template <int N>
  Eigen::Matrix<float, N, 1> vec(const json& v, const std::string& path) const {
    if (!v.is_array() || v.size() != N)
      fail_at(path, "expected an array of " + std::to_string(N) + " numbers");
    Eigen::Matrix<float, N, 1> out;
    for (int i = 0; i < N; ++i) {
      if (!v[i].is_number()) fail_at(path + "/" + std::to_string(i), "expected a number");
      out[i] = v[i].get<float>();
      if (!std::isfinite(out[i]))
        fail_at(path + "/" + std::to_string(i), "expected a finite number");
    }
    return out;
  }

  static std::string fmt(float f) {
    std::string s = std::to_string(f);
    while (s.size() > 1 && s.back() == '0') s.pop_back();
    if (s.back() == '.') s.pop_back();
    return s;
  }

 private:
  const json& j_;
  std::string origin_;
  std::string path_;
};

template <int N>
json to_array(const Eigen::Matrix<float, N, 1>& v) {
  json a = json::array();
  for (int i = 0; i < N; ++i) a.push_back(v[i]);
  return a;
}

// ---- dump ---------------------------------------------------------------------------------

json texture_json(const Texture& t) {
  json j = {{"kind", texture_kind_name(t.kind)}};
  if (t.kind == TextureKind::kNone) return j;
  if (t.kind == TextureKind::kImage) {
    j["path"] = t.path;
    return j;
  }
  if (t.kind == TextureKind::kImageDetail) {
    j["path"] = t.path;
    j["scale"] = t.scale;
    return j;
  }
  j["color_a"] = to_array<3>(t.color_a);
  j["color_b"] = to_array<3>(t.color_b);
  j["scale"] = t.scale;
  j["turbulence"] = t.turbulence;
  j["seed"] = t.seed;
  return j;
}

json mesh_json(const Mesh& m) {
  json j = {{"name", m.name}};
  if (m.primitive) {
    j["primitive"] = {{"type", m.primitive->type},
                      {"size", to_array<3>(m.primitive->size)},
                      {"segments", m.primitive->segments}};
    return j;
  }
  json p = json::array(), n = json::array(), uv = json::array(), t = json::array(),
       motion = json::array();
  for (const auto& v : m.positions) p.push_back(to_array<3>(v));
  for (const auto& v : m.motion) motion.push_back(to_array<3>(v));
  for (const auto& v : m.normals) n.push_back(to_array<3>(v));
  for (const auto& v : m.uvs) uv.push_back(to_array<2>(v));
  for (const auto& v : m.triangles) t.push_back({v.x(), v.y(), v.z()});
  j["positions"] = p;
  if (!m.normals.empty()) j["normals"] = n;
  if (!m.uvs.empty()) j["uvs"] = uv;
  j["triangles"] = t;
  if (!m.motion.empty()) j["motion"] = motion;
  return j;
}

}  // namespace

const char* texture_kind_name(TextureKind kind) { return kTextureKinds[static_cast<int>(kind)]; }

json scene_to_json(const Scene& s) {
  json j;
  j["seed"] = s.seed;
  const Camera& c = s.camera;
  j["camera"] = {
      {"position", to_array<3>(c.position)},
      {"orientation", {c.orientation.w(), c.orientation.x(), c.orientation.y(), c.orientation.z()}},
      {"vfov_deg", c.vfov_deg},
      {"focal_length_mm", c.focal_length_mm},
      {"sensor_height_mm", c.sensor_height_mm},
      {"aperture_radius", c.aperture_radius},
      {"focus_distance", c.focus_distance},
      {"width", c.width},
      {"height", c.height}};
  j["meshes"] = json::array();
  for (const auto& m : s.meshes) j["meshes"].push_back(mesh_json(m));
  j["materials"] = json::array();
  for (const auto& m : s.materials) {
    json material = {{"name", m.name},
                     {"diffuse", to_array<3>(m.diffuse)},
                     {"specular", m.specular},
                     {"shininess", m.shininess},
                     {"hue_offset_deg", m.hue_offset_deg},
                     {"texture", texture_json(m.texture)}};
    if (m.strands_per_uv > 0) {  // keys only when used: opaque materials keep their old text
      material["strands_per_uv"] = m.strands_per_uv;
      material["strand_coverage"] = m.strand_coverage;
    }
    j["materials"].push_back(std::move(material));
  }
  j["instances"] = json::array();
  for (const auto& i : s.instances) {
    json rows = json::array();
    for (int r = 0; r < 4; ++r) {
      rows.push_back({i.transform(r, 0), i.transform(r, 1), i.transform(r, 2), i.transform(r, 3)});
    }
    j["instances"].push_back({{"name", i.name},
                              {"mesh", i.mesh},
                              {"material", i.material},
                              {"transform", rows},
                              {"instance_id", i.instance_id},
                              {"semantic_id", i.semantic_id}});
  }
  json sun = {{"enabled", s.sun.enabled},
              {"color", to_array<3>(s.sun.color)},
              {"intensity", s.sun.intensity},
              {"angular_radius_deg", s.sun.angular_radius_deg}};
  if (s.sun.solar) {
    sun["solar"] = {{"hour", s.sun.solar->hour},
                    {"day_of_year", s.sun.solar->day_of_year},
                    {"latitude_deg", s.sun.solar->latitude_deg}};
  } else {
    sun["direction"] = to_array<3>(s.sun.direction);
  }
  j["sun"] = sun;
  j["point_lights"] = json::array();
  for (const auto& l : s.point_lights) {
    j["point_lights"].push_back({{"position", to_array<3>(l.position)},
                                 {"color", to_array<3>(l.color)},
                                 {"intensity", l.intensity},
                                 {"radius", l.radius},
                                 {"on", l.on}});
  }
  if (s.environment) {
    j["environment"] = {{"path", s.environment->path},
                        {"color", to_array<3>(s.environment->color)},
                        {"intensity", s.environment->intensity},
                        {"rotation_deg", s.environment->rotation_deg}};
  }
  const PostProcess& p = s.post;
  j["post"] = {{"exposure_ev", p.exposure_ev},
               {"temperature", p.temperature},
               {"contrast", p.contrast},
               {"saturation", p.saturation},
               {"vignette", p.vignette},
               {"bloom", p.bloom},
               {"bloom_threshold", p.bloom_threshold},
               {"film_grain", p.film_grain},
               {"lens_blur", p.lens_blur}};
  // The camera model's keys only when used, so scenes without it keep their bytes.
  if (p.auto_exposure_key > 0) j["post"]["auto_exposure_key"] = p.auto_exposure_key;
  if (p.shot_noise > 0) j["post"]["shot_noise"] = p.shot_noise;
  if (p.read_noise > 0) j["post"]["read_noise"] = p.read_noise;
  if (p.filmic) j["post"]["filmic"] = true;
  j["background"] = {{"color", to_array<3>(s.background.color)},
                     {"texture", texture_json(s.background.texture)},
                     {"image", s.background.image}};
  return j;
}

namespace {

Texture read_texture(const Reader& r) {
  r.allow({"kind", "path", "color_a", "color_b", "scale", "turbulence", "seed"});
  Texture t;
  std::string kind = "none";
  r.read("kind", kind);
  bool found = false;
  for (std::size_t i = 0; i < kTextureKinds.size(); ++i) {
    if (kind == kTextureKinds[i]) {
      t.kind = static_cast<TextureKind>(i);
      found = true;
    }
  }
  if (!found) {
    r.fail_at(r.at("kind"),
              "unknown texture kind '" + kind +
                  "' (none, image, noise, stripes, checker, fabric, wood, marble, image_detail)");
  }
  r.read("path", t.path);
  if (texture_has_image(t.kind) && t.path.empty())
    r.fail_at(r.at("path"), "image texture needs a path");
  r.read("color_a", t.color_a);
  r.read("color_b", t.color_b);
  r.read_range("scale", t.scale, 1e-6f, 1e6f);
  r.read_range("turbulence", t.turbulence, 0.0f, 100.0f);
  r.read("seed", t.seed);
  return t;
}

Mesh read_mesh(const Reader& r) {
  r.allow({"name", "primitive", "positions", "normals", "uvs", "triangles", "motion"});
  std::string name;
  r.read("name", name);
  Mesh m;
  if (r.has("primitive")) {
    const Reader p = r.child("primitive");
    p.allow({"type", "size", "segments"});
    PrimitiveSpec spec;
    p.read("type", spec.type);
    p.read("size", spec.size);
    p.read("segments", spec.segments, 1, 4096);
    try {
      m = make_primitive(spec);
    } catch (const Error& e) {
      r.fail_at(r.at("primitive"), e.what());
    }
    m.name = name;
    return m;
  }
  m.name = name;
  if (!r.has("positions") || !r.has("triangles")) {
    r.fail("a mesh needs 'primitive' or 'positions' and 'triangles'");
  }
  auto read_list = [&](const char* key, auto& out, auto convert) {
    if (!r.has(key)) return;
    const json& a = r.raw(key);
    if (!a.is_array()) r.fail_at(r.at(key), "expected an array");
    for (std::size_t i = 0; i < a.size(); ++i)
      out.push_back(convert(a[i], r.at(key) + "/" + std::to_string(i)));
  };
  read_list("positions", m.positions,
            [&](const json& v, const std::string& p) { return r.vec<3>(v, p); });
  read_list("normals", m.normals,
            [&](const json& v, const std::string& p) { return r.vec<3>(v, p); });
  read_list("uvs", m.uvs, [&](const json& v, const std::string& p) { return r.vec<2>(v, p); });
  read_list("motion", m.motion,
            [&](const json& v, const std::string& p) { return r.vec<3>(v, p); });
  const int count = static_cast<int>(m.positions.size());
  read_list("triangles", m.triangles, [&](const json& v, const std::string& p) {
    if (!v.is_array() || v.size() != 3) r.fail_at(p, "expected 3 vertex indices");
    Eigen::Vector3i t;
    for (int k = 0; k < 3; ++k) {
      if (!v[k].is_number_integer() || v[k].get<std::int64_t>() < 0 ||
          v[k].get<std::int64_t>() >= count) {
        r.fail_at(p + "/" + std::to_string(k),
                  "vertex index out of range 0.." + std::to_string(count - 1));
      }
      t[k] = v[k].get<int>();
    }
    return t;
  });
  if (!m.normals.empty() && m.normals.size() != m.positions.size()) {
    r.fail_at(r.at("normals"), "needs one normal per position");
  }
  if (!m.uvs.empty() && m.uvs.size() != m.positions.size()) {
    r.fail_at(r.at("uvs"), "needs one uv per position");
  }
  if (!m.motion.empty() && m.motion.size() != m.positions.size()) {
    r.fail_at(r.at("motion"), "needs one motion vector per position");
  }
  return m;
}

Eigen::Matrix4f read_transform(const Reader& r, const char* key) {
  const json& rows = r.raw(key);
  if (!rows.is_array() || rows.size() != 4) r.fail_at(r.at(key), "expected 4 rows of 4 numbers");
  Eigen::Matrix4f m;
  for (int i = 0; i < 4; ++i)
    m.row(i) = r.vec<4>(rows[i], r.at(key) + "/" + std::to_string(i)).transpose();
  if (m.row(3) != Eigen::RowVector4f(0, 0, 0, 1))
    r.fail_at(r.at(key) + "/3", "last row must be [0, 0, 0, 1]");
  if (std::abs(m.topLeftCorner<3, 3>().determinant()) < 1e-12f)
    r.fail_at(r.at(key), "transform is singular");
  return m;
}

Eigen::Quaternionf euler_xyz_deg(const Eigen::Vector3f& deg) {
  const float k = std::numbers::pi_v<float> / 180.0f;
  return Eigen::AngleAxisf(deg.z() * k, Eigen::Vector3f::UnitZ()) *
         Eigen::AngleAxisf(deg.y() * k, Eigen::Vector3f::UnitY()) *
         Eigen::AngleAxisf(deg.x() * k, Eigen::Vector3f::UnitX());
}

Camera read_camera(const Reader& r) {
  r.allow({"position", "orientation", "look_at", "up", "vfov_deg", "focal_length_mm",
           "sensor_height_mm", "aperture_radius", "focus_distance", "width", "height"});
  Camera c;
  r.read("position", c.position);
  if (r.has("orientation") && r.has("look_at")) r.fail("give 'orientation' or 'look_at', not both");
  if (r.has("orientation")) {
    const Eigen::Vector4f q = r.vec<4>(r.raw("orientation"), r.at("orientation"));
    if (q.norm() < 1e-6f) r.fail_at(r.at("orientation"), "quaternion must not be zero");
    c.orientation = Eigen::Quaternionf(q[0], q[1], q[2], q[3]);
    // Written exactly as given when already unit, so dumps round-trip bit for bit.
    if (std::abs(q.norm() - 1.0f) > 1e-5f) c.orientation.normalize();
  }
  if (r.has("look_at")) {
    const Eigen::Vector3f target = r.vec<3>(r.raw("look_at"), r.at("look_at"));
    Eigen::Vector3f up(0, 1, 0);
    r.read("up", up);
    const Eigen::Vector3f back = c.position - target;
    if (back.norm() < 1e-6f) r.fail_at(r.at("look_at"), "target equals the camera position");
    const Eigen::Vector3f z = back.normalized();
    const Eigen::Vector3f x = up.cross(z);
    if (x.norm() < 1e-6f) r.fail_at(r.at("up"), "up is parallel to the view direction");
    Eigen::Matrix3f rot;
    rot.col(0) = x.normalized();
    rot.col(2) = z;
    rot.col(1) = z.cross(rot.col(0));
    c.orientation = Eigen::Quaternionf(rot);
  }
  r.read_range("vfov_deg", c.vfov_deg, 0.01f, 179.0f);
  r.read_range("focal_length_mm", c.focal_length_mm, 0.0f, 10000.0f);
  r.read_range("sensor_height_mm", c.sensor_height_mm, 0.01f, 1000.0f);
  r.read_range("aperture_radius", c.aperture_radius, 0.0f, 10.0f);
  r.read_range("focus_distance", c.focus_distance, 0.001f, 1e6f);
  r.read("width", c.width, 1, 16384);
  r.read("height", c.height, 1, 16384);
  return c;
}

Material read_material(const Reader& r) {
  r.allow({"name", "diffuse", "specular", "shininess", "hue_offset_deg", "texture",
           "strands_per_uv", "strand_coverage"});
  Material m;
  r.read("name", m.name);
  r.read("diffuse", m.diffuse);
  r.read_range("specular", m.specular, 0.0f, 100.0f);
  r.read_range("shininess", m.shininess, 0.0f, 1e5f);
  r.read_range("hue_offset_deg", m.hue_offset_deg, -360.0f, 360.0f);
  r.read_range("strands_per_uv", m.strands_per_uv, 0.0f, 1e4f);
  r.read_range("strand_coverage", m.strand_coverage, 0.05f, 1.0f);
  if (r.has("texture")) m.texture = read_texture(r.child("texture"));
  return m;
}

// An instance of one of `scene`'s meshes with one of its materials, placed by a 4×4
// 'transform' or by translation, rotation_deg (X, then Y, then Z, extrinsic) and scale.
Instance read_instance(const Reader& r, const Scene& scene) {
  r.allow({"name", "mesh", "material", "transform", "translation", "rotation_deg", "scale",
           "instance_id", "semantic_id"});
  Instance in;
  r.read("name", in.name);
  if (!r.has("mesh")) r.fail("missing 'mesh' (an index into /meshes)");
  r.read("mesh", in.mesh, 0, static_cast<int>(scene.meshes.size()) - 1);
  if (scene.materials.empty()) r.fail("no materials are defined");
  r.read("material", in.material, 0, static_cast<int>(scene.materials.size()) - 1);
  if (r.has("transform")) {
    if (r.has("translation") || r.has("rotation_deg") || r.has("scale")) {
      r.fail("give 'transform' or translation/rotation_deg/scale, not both");
    }
    in.transform = read_transform(r, "transform");
  } else {
    Eigen::Vector3f t = Eigen::Vector3f::Zero(), rot = Eigen::Vector3f::Zero(),
                    sc = Eigen::Vector3f::Ones();
    r.read("translation", t);
    r.read("rotation_deg", rot);
    r.read("scale", sc);
    if ((sc.array().abs() < 1e-9f).any()) r.fail_at(r.at("scale"), "scale must not be zero");
    Eigen::Affine3f a = Eigen::Translation3f(t) * euler_xyz_deg(rot) * Eigen::Scaling(sc);
    in.transform = a.matrix();
  }
  int id = 0;
  r.read("instance_id", id, 0, 65535);
  in.instance_id = static_cast<std::uint16_t>(id);
  id = 0;
  r.read("semantic_id", id, 0, 65535);
  in.semantic_id = static_cast<std::uint16_t>(id);
  return in;
}

// The sun, by 'direction' or by a 'solar' position (hour, day of year, latitude).
void read_sun(const Reader& r, Sun& sun) {
  r.allow({"enabled", "direction", "solar", "color", "intensity", "angular_radius_deg"});
  r.read("enabled", sun.enabled);
  if (r.has("direction") && r.has("solar")) r.fail("give 'direction' or 'solar', not both");
  r.read("direction", sun.direction);
  if (sun.direction.norm() < 1e-6f) r.fail_at(r.at("direction"), "direction must not be zero");
  if (r.has("solar")) {
    const Reader p = r.child("solar");
    p.allow({"hour", "day_of_year", "latitude_deg"});
    SolarPosition sp;
    p.read_range("hour", sp.hour, 0.0f, 24.0f);
    p.read_range("day_of_year", sp.day_of_year, 0.0f, 366.0f);
    p.read_range("latitude_deg", sp.latitude_deg, -90.0f, 90.0f);
    sun.solar = sp;
  }
  r.read("color", sun.color);
  r.read_range("intensity", sun.intensity, 0.0f, 1e9f);
  r.read_range("angular_radius_deg", sun.angular_radius_deg, 0.0f, 45.0f);
}

PointLight read_point_light(const Reader& r) {
  r.allow({"position", "color", "intensity", "radius", "on"});
  PointLight l;
  r.read("position", l.position);
  r.read("color", l.color);
  r.read_range("intensity", l.intensity, 0.0f, 1e9f);
  r.read_range("radius", l.radius, 0.0f, 1e3f);
  r.read("on", l.on);
  return l;
}

Environment read_environment(const Reader& r) {
  r.allow({"path", "color", "intensity", "rotation_deg"});
  Environment e;
  r.read("path", e.path);
  r.read("color", e.color);
  r.read_range("intensity", e.intensity, 0.0f, 1e9f);
  r.read("rotation_deg", e.rotation_deg);
  return e;
}

void read_post(const Reader& r, PostProcess& p) {
  r.allow({"exposure_ev", "temperature", "contrast", "saturation", "vignette", "bloom",
           "bloom_threshold", "film_grain", "lens_blur", "auto_exposure_key", "shot_noise",
           "read_noise", "filmic"});
  r.read_range("exposure_ev", p.exposure_ev, -20.0f, 20.0f);
  r.read_range("temperature", p.temperature, -100.0f, 100.0f);
  r.read_range("contrast", p.contrast, -100.0f, 100.0f);
  r.read_range("saturation", p.saturation, -100.0f, 100.0f);
  r.read_range("vignette", p.vignette, 0.0f, 1.0f);
  r.read_range("bloom", p.bloom, 0.0f, 1.0f);
  r.read_range("bloom_threshold", p.bloom_threshold, 0.0f, 1e6f);
  r.read_range("film_grain", p.film_grain, 0.0f, 1.0f);
  r.read_range("lens_blur", p.lens_blur, 0.0f, 64.0f);
  r.read_range("auto_exposure_key", p.auto_exposure_key, 0.0f, 1.0f);
  r.read_range("shot_noise", p.shot_noise, 0.0f, 1.0f);
  r.read_range("read_noise", p.read_noise, 0.0f, 1.0f);
  r.read("filmic", p.filmic);
}

void read_background(const Reader& r, Background& background) {
  r.allow({"color", "texture", "image"});
  r.read("color", background.color);
  if (r.has("texture")) background.texture = read_texture(r.child("texture"));
  r.read("image", background.image);
}

}  // namespace

Scene scene_from_json(const json& j, const std::string& origin) {
  const Reader root(j, origin, "");
  root.allow({"seed", "camera", "meshes", "materials", "instances", "sun", "point_lights",
              "environment", "post", "background"});
  Scene s;
  root.read("seed", s.seed);
  if (root.has("camera")) s.camera = read_camera(root.child("camera"));

  auto each = [&](const char* key, auto fn) {
    if (!root.has(key)) return;
    const json& a = root.raw(key);
    if (!a.is_array()) root.fail_at(root.at(key), "expected an array");
    for (std::size_t i = 0; i < a.size(); ++i) {
      fn(Reader(a[i], origin, root.at(key) + "/" + std::to_string(i)));
    }
  };
  each("meshes", [&](const Reader& r) { s.meshes.push_back(read_mesh(r)); });
  each("materials", [&](const Reader& r) { s.materials.push_back(read_material(r)); });
  each("instances", [&](const Reader& r) { s.instances.push_back(read_instance(r, s)); });
  if (root.has("sun")) read_sun(root.child("sun"), s.sun);
  each("point_lights", [&](const Reader& r) { s.point_lights.push_back(read_point_light(r)); });
  if (root.has("environment")) s.environment = read_environment(root.child("environment"));
  if (root.has("post")) read_post(root.child("post"), s.post);
  if (root.has("background")) read_background(root.child("background"), s.background);
  return s;
}

Scene parse_scene(const std::string& text, const std::string& origin) {
  json j;
  try {
    j = json::parse(text);
  } catch (const json::parse_error& e) {
    // nlohmann's message already says "at line L, column C".
    throw Error(origin + ": malformed JSON: " + e.what());
  }
  return scene_from_json(j, origin);
}

Scene load_scene(const std::filesystem::path& path) {
  Scene s = parse_scene(read_file(path), path.string());
  s.base_dir = path.parent_path().string();
  // Referenced files must exist now, so a typo fails before any rendering starts.
  auto require = [&](const std::string& file, const std::string& json_path) {
    if (file.empty()) return;
    const std::string resolved = resolve_path(s, file);
    // An archive's entry is checked when the renderer reads it; the archive itself here.
    const std::optional<ArchiveMember> member = archive_member(resolved);
    if (!std::filesystem::is_regular_file(member ? member->archive.string() : resolved)) {
      throw Error(path.string() + ": " + json_path + ": file '" + resolved + "' not found");
    }
  };
  for (std::size_t i = 0; i < s.materials.size(); ++i) {
    if (texture_has_image(s.materials[i].texture.kind)) {
      require(s.materials[i].texture.path, "/materials/" + std::to_string(i) + "/texture/path");
    }
  }
  if (texture_has_image(s.background.texture.kind)) {
    require(s.background.texture.path, "/background/texture/path");
  }
  require(s.background.image, "/background/image");
  if (s.environment) require(s.environment->path, "/environment/path");
  return s;
}

std::string dump_scene(const Scene& scene) { return scene_to_json(scene).dump(2) + "\n"; }

}  // namespace wheelpose::scene
