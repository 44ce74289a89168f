#include "motion/clip_json.h"

#include <cmath>

#include "core/atomic_file.h"
#include "core/error.h"

namespace wheelpose::motion {

namespace {

constexpr const char* kFormat = "wheelpose.seated_clip";
constexpr int kVersion = 1;

// Rounds to `digits` decimals; dividing by the power of ten (not multiplying by its inverse)
// yields the double nearest the decimal, which prints short.
double round_to(double value, double scale) {
  const double rounded = std::round(value * scale) / scale;
  return rounded == 0.0 ? 0.0 : rounded;  // no "-0"
}

nlohmann::ordered_json vec3(const Eigen::Vector3d& v) {
  return {round_to(v.x(), 1e6), round_to(v.y(), 1e6), round_to(v.z(), 1e6)};
}

nlohmann::ordered_json quat(const Eigen::Quaterniond& q) {
  return {round_to(q.w(), 1e7), round_to(q.x(), 1e7), round_to(q.y(), 1e7), round_to(q.z(), 1e7)};
}

class Reader {
 public:
  explicit Reader(std::filesystem::path path) : path_(std::move(path)) {}
  [[noreturn]] void fail(const std::string& field, const std::string& what) const {
    throw Error(path_.string() + ": " + field + ": " + what);
  }
  const nlohmann::ordered_json& member(const nlohmann::ordered_json& object, const std::string& key) const {
    if (!object.is_object() || !object.contains(key)) fail(key, "missing");
    return object.at(key);
  }
  std::vector<double> numbers(const nlohmann::ordered_json& value, std::size_t count,
                              const std::string& field) const {
    if (!value.is_array() || value.size() != count) {
      fail(field, "expected " + std::to_string(count) + " numbers");
    }
    std::vector<double> out;
    for (const auto& item : value) {
      if (!item.is_number()) fail(field, "expected a number");
      out.push_back(item.get<double>());
    }
    return out;
  }
  const nlohmann::ordered_json& frames(const nlohmann::ordered_json& value, std::size_t count,
                               const std::string& field) const {
    if (!value.is_array() || value.size() != count) {
      fail(field, "expected " + std::to_string(count) + " entries");
    }
    return value;
  }

 private:
  std::filesystem::path path_;
};

}  // namespace

nlohmann::ordered_json seated_clip_to_json(const SeatedClip& clip) {
  const SkeletalMotion& m = clip.motion;
  nlohmann::ordered_json joints = nlohmann::ordered_json::array();
  nlohmann::ordered_json parents = nlohmann::ordered_json::array();
  nlohmann::ordered_json offsets = nlohmann::ordered_json::array();
  for (int j = 0; j < kJointCount; ++j) {
    joints.push_back(std::string(joint_name(j)));
    parents.push_back(joint_parent(j));
    offsets.push_back(vec3(m.rest_offsets[j]));
  }
  nlohmann::ordered_json roots = nlohmann::ordered_json::array();
  nlohmann::ordered_json rotations = nlohmann::ordered_json::array();
  nlohmann::ordered_json positions = nlohmann::ordered_json::array();
  for (std::size_t f = 0; f < m.frame_count(); ++f) {
    roots.push_back(vec3(m.root_positions[f]));
    nlohmann::ordered_json frame_rotations = nlohmann::ordered_json::array();
    nlohmann::ordered_json frame_positions = nlohmann::ordered_json::array();
    for (int j = 0; j < kJointCount; ++j) {
      frame_rotations.push_back(quat(m.local_rotations[f][j]));
      frame_positions.push_back(vec3(clip.positions[f][j]));
    }
    rotations.push_back(std::move(frame_rotations));
    positions.push_back(std::move(frame_positions));
  }
  return {{"format", kFormat},
          {"version", kVersion},
          {"name", m.name},
          {"fps", m.fps},
          {"frame_count", m.frame_count()},
          {"frame", {{"units", "metres"}, {"up", "+Y"}, {"facing", "+Z"}, {"left", "+X"}}},
          {"skeleton", {{"joints", joints}, {"parents", parents}, {"rest_offsets", offsets}}},
          {"root_positions", roots},
          {"local_rotations", rotations},
          {"positions", positions},
          {"provenance", clip.provenance}};
}

std::string seated_clip_json_text(const SeatedClip& clip) {
  return seated_clip_to_json(clip).dump() + "\n";
}

void write_seated_clip_json(const SeatedClip& clip, const std::filesystem::path& path) {
  write_file_atomic(path, seated_clip_json_text(clip));
}

SeatedClip read_seated_clip_json(const std::filesystem::path& path) {
  Reader r(path);
  nlohmann::ordered_json doc;
  try {
    doc = nlohmann::ordered_json::parse(read_file(path));
  } catch (const nlohmann::ordered_json::parse_error& e) {
    throw Error(path.string() + ": invalid JSON: " + e.what());
  }
  if (r.member(doc, "format") != kFormat) r.fail("format", "not a WheelPose seated clip");
  if (r.member(doc, "version") != kVersion) r.fail("version", "unsupported version");
  SeatedClip clip;
  SkeletalMotion& m = clip.motion;
  const auto& name = r.member(doc, "name");
  if (!name.is_string()) r.fail("name", "expected a string");
  m.name = name.get<std::string>();
  const auto& fps = r.member(doc, "fps");
  if (!fps.is_number() || !(fps.get<double>() > 0)) r.fail("fps", "expected a positive number");
  m.fps = fps.get<double>();
  const auto& count_json = r.member(doc, "frame_count");
  if (!count_json.is_number_unsigned()) r.fail("frame_count", "expected a count");
  const std::size_t count = count_json.get<std::size_t>();

  const auto& skeleton = r.member(doc, "skeleton");
  const auto& joints = r.frames(r.member(skeleton, "joints"), kJointCount, "skeleton.joints");
  for (int j = 0; j < kJointCount; ++j) {
    if (joints[j] != std::string(joint_name(j))) {
      r.fail("skeleton.joints[" + std::to_string(j) + "]", "expected " + std::string(joint_name(j)));
    }
  }
  const auto& offsets =
      r.frames(r.member(skeleton, "rest_offsets"), kJointCount, "skeleton.rest_offsets");
  for (int j = 0; j < kJointCount; ++j) {
    auto v = r.numbers(offsets[j], 3, "skeleton.rest_offsets[" + std::to_string(j) + "]");
    m.rest_offsets[j] = {v[0], v[1], v[2]};
  }
  const auto& roots = r.frames(r.member(doc, "root_positions"), count, "root_positions");
  const auto& rotations = r.frames(r.member(doc, "local_rotations"), count, "local_rotations");
  const auto& positions = r.frames(r.member(doc, "positions"), count, "positions");
  m.root_positions.resize(count);
  m.local_rotations.resize(count);
  clip.positions.resize(count);
  for (std::size_t f = 0; f < count; ++f) {
    const std::string frame = "[" + std::to_string(f) + "]";
    auto root = r.numbers(roots[f], 3, "root_positions" + frame);
    m.root_positions[f] = {root[0], root[1], root[2]};
    r.frames(rotations[f], kJointCount, "local_rotations" + frame);
    r.frames(positions[f], kJointCount, "positions" + frame);
    for (int j = 0; j < kJointCount; ++j) {
      const std::string field = frame + "[" + std::to_string(j) + "]";
      auto q = r.numbers(rotations[f][j], 4, "local_rotations" + field);
      // Kept as stored (unit to 1e-7) so that writing it again gives the same bytes.
      m.local_rotations[f][j] = Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
      auto p = r.numbers(positions[f][j], 3, "positions" + field);
      clip.positions[f][j] = {p[0], p[1], p[2]};
    }
  }
  if (doc.contains("provenance")) clip.provenance = doc["provenance"];
  return clip;
}

}  // namespace wheelpose::motion
