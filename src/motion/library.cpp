#include "motion/library.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <set>

#include "core/config.h"
#include "core/error.h"
#include "core/random.h"

namespace wheelpose::motion {

// Defined in the source file CMake generates from data/motions/*.yaml.
struct EmbeddedMotionFile {
  const char* name;
  const char* text;
};
extern const EmbeddedMotionFile kEmbeddedMotionFiles[];
extern const std::size_t kEmbeddedMotionFileCount;

namespace {

using Eigen::AngleAxisd;
using Eigen::Quaterniond;
using Eigen::Vector3d;

constexpr double kDegToRad = std::numbers::pi / 180.0;

struct ChannelLimits {
  double min;
  double max;
};

// Authoring limits per channel (degrees). They keep every variant inside normal adult ranges of
// motion; data/motions/README.md lists them with the sign conventions.
const std::map<std::string, ChannelLimits>& channel_limits() {
  static const std::map<std::string, ChannelLimits> limits = [] {
    std::map<std::string, ChannelLimits> table = {
        {"body_yaw", {-180, 180}}, {"pelvis_tilt", {-15, 40}}, {"trunk_flexion", {-20, 75}},
        {"trunk_bend", {-30, 30}}, {"trunk_twist", {-40, 40}}, {"head_nod", {-40, 40}},
        {"head_tilt", {-35, 35}},  {"head_turn", {-60, 60}},
    };
    for (const char* segment : {"spine", "chest", "upper_chest"}) {
      table[std::string(segment) + "_flexion"] = {-10, 30};
      table[std::string(segment) + "_bend"] = {-15, 15};
      table[std::string(segment) + "_twist"] = {-20, 20};
    }
    for (const char* side : {"left", "right"}) {
      const std::string s = side;
      table[s + "_clavicle_elevation"] = {-10, 35};
      table[s + "_clavicle_protraction"] = {-25, 25};
      table[s + "_shoulder_elevation"] = {0, 175};
      table[s + "_shoulder_plane"] = {-90, 145};
      table[s + "_shoulder_rotation"] = {-90, 90};
      table[s + "_elbow_flexion"] = {0, 150};
    }
    return table;
  }();
  return limits;
}

// How trunk_* shorthands spread over the three spine joints.
constexpr double kTrunkShare[3] = {0.4, 0.35, 0.25};

struct LoadedLibrary {
  std::vector<MotionDefinition> motions;  // sorted by id
};

std::string file_stem(const std::string& origin) {
  std::string name = origin.substr(origin.find_last_of('/') + 1);
  const auto dot = name.rfind('.');
  return dot == std::string::npos ? name : name.substr(0, dot);
}

const LoadedLibrary& loaded_library() {
  static const LoadedLibrary library = [] {
    LoadedLibrary result;
    std::set<std::string> ids;
    for (std::size_t i = 0; i < kEmbeddedMotionFileCount; ++i) {
      const std::string origin = std::string("data/motions/") + kEmbeddedMotionFiles[i].name;
      MotionDefinition motion = parse_motion_definition(kEmbeddedMotionFiles[i].text, origin);
      if (!ids.insert(motion.id).second) {
        throw Error(origin + ": duplicate motion id '" + motion.id + "'");
      }
      result.motions.push_back(std::move(motion));
    }
    std::sort(result.motions.begin(), result.motions.end(),
              [](const MotionDefinition& a, const MotionDefinition& b) { return a.id < b.id; });
    return result;
  }();
  return library;
}

const MotionDefinition& find_motion(const std::string& id) {
  for (const MotionDefinition& motion : loaded_library().motions) {
    if (motion.id == id) return motion;
  }
  throw Error("unknown library motion '" + id + "' (" +
              std::to_string(loaded_library().motions.size()) + " built-in motions exist)");
}

// Cubic Hermite through the keys with Catmull-Rom tangents (zero tangents at the ends of a
// non-looping track so motions ease in and out); loops wrap around t = 1.
double evaluate_track(const ChannelTrack& track, double t, bool loop) {
  const auto& k = track.keys;
  const std::size_t n = k.size();
  if (n == 1) return k[0].second;
  if (loop) t -= std::floor(t);
  // Keys as a function of index with periodic extension for loops.
  auto key_at = [&](long i) -> std::pair<double, double> {
    if (!loop) {
      const long clamped = std::clamp<long>(i, 0, static_cast<long>(n) - 1);
      return k[static_cast<std::size_t>(clamped)];
    }
    const long size = static_cast<long>(n);
    const long wraps = (i >= 0 ? i / size : -((-i + size - 1) / size));
    const auto& key = k[static_cast<std::size_t>(i - wraps * size)];
    return {key.first + static_cast<double>(wraps), key.second};
  };
  long segment;
  if (!loop) {
    if (t <= k.front().first) return k.front().second;
    if (t >= k.back().first) return k.back().second;
    segment = 0;
    while (k[static_cast<std::size_t>(segment) + 1].first < t) ++segment;
  } else {
    segment = -1;
    while (segment + 1 < static_cast<long>(n) &&
           k[static_cast<std::size_t>(segment + 1)].first <= t) {
      ++segment;
    }
  }
  const auto [t0, p0] = key_at(segment);
  const auto [t1, p1] = key_at(segment + 1);
  auto tangent = [&](long i) {
    if (!loop && (i <= 0 || i >= static_cast<long>(n) - 1)) return 0.0;
    const auto [ta, pa] = key_at(i - 1);
    const auto [tb, pb] = key_at(i + 1);
    return (pb - pa) / (tb - ta);
  };
  const double h = t1 - t0;
  const double m0 = tangent(segment) * h;
  const double m1 = tangent(segment + 1) * h;
  const double s = (t - t0) / h;
  const double s2 = s * s;
  const double s3 = s2 * s;
  return (2 * s3 - 3 * s2 + 1) * p0 + (s3 - 2 * s2 + s) * m0 + (-2 * s3 + 3 * s2) * p1 +
         (s3 - s2) * m1;
}

double oscillator_value(const Oscillator& osc, double t, bool loop) {
  if (loop) t -= std::floor(t);
  if (t < osc.start || t > osc.end) return 0.0;
  double envelope = 1.0;
  if (osc.start > 0.0 || osc.end < 1.0) {
    // Raised-cosine fades over the first and last 15% of the window so the channel stays smooth.
    const double fade = 0.15 * (osc.end - osc.start);
    const double u = std::min(t - osc.start, osc.end - t) / fade;
    if (u < 1.0) envelope = 0.5 - 0.5 * std::cos(std::numbers::pi * u);
  }
  return envelope * osc.amplitude * std::sin(2 * std::numbers::pi * (osc.cycles * t + osc.phase));
}

Quaterniond rot(const Vector3d& axis, double degrees) {
  return Quaterniond(AngleAxisd(degrees * kDegToRad, axis.normalized()));
}

double channel(const std::map<std::string, double>& values, const std::string& name) {
  const auto it = values.find(name);
  return it == values.end() ? 0.0 : it->second;
}

// Local rotation of a spine segment: twist about the vertical, lateral bend, flexion.
Quaterniond segment_rotation(double flexion, double bend, double twist) {
  return rot(Vector3d::UnitY(), twist) * rot(Vector3d::UnitZ(), -bend) *
         rot(Vector3d::UnitX(), flexion);
}

// Global (thorax-relative) rotation of the upper arm: axial rotation of the hanging arm, then a
// swing of `elevation` degrees towards the azimuth `plane` (0 = sideways, 90 = forward).
Quaterniond upper_arm_rotation(bool left, double elevation, double plane, double rotation) {
  const double p = plane * kDegToRad;
  const double sign = left ? 1.0 : -1.0;
  const Vector3d axis(-std::sin(p), 0.0, sign * std::cos(p));
  const Quaterniond axial = rot(Vector3d::UnitY(), -sign * rotation);
  const Quaterniond rest_to_hanging = rot(Vector3d::UnitZ(), -sign * 90.0);
  return rot(axis, elevation) * axial * rest_to_hanging;
}

PoseRotations global_pose(const std::map<std::string, double>& c) {
  PoseRotations g;
  const Quaterniond yaw = rot(Vector3d::UnitY(), channel(c, "body_yaw"));
  g[kPelvis] = yaw * rot(Vector3d::UnitX(), channel(c, "pelvis_tilt"));
  const char* segments[3] = {"spine", "chest", "upper_chest"};
  const int joints[3] = {kSpine, kChest, kUpperChest};
  Quaterniond parent = g[kPelvis];
  for (int i = 0; i < 3; ++i) {
    const std::string s = segments[i];
    const double flexion =
        channel(c, s + "_flexion") + kTrunkShare[i] * channel(c, "trunk_flexion");
    const double bend = channel(c, s + "_bend") + kTrunkShare[i] * channel(c, "trunk_bend");
    const double twist = channel(c, s + "_twist") + kTrunkShare[i] * channel(c, "trunk_twist");
    g[joints[i]] = parent * segment_rotation(flexion, bend, twist);
    parent = g[joints[i]];
  }
  const Quaterniond thorax = g[kUpperChest];
  // The neck joint stays with the thorax so that head motion never drags the clavicles along.
  g[kNeckBase] = thorax;
  g[kHeadBase] = thorax * segment_rotation(channel(c, "head_nod"), channel(c, "head_tilt"),
                                           channel(c, "head_turn"));
  g[kHeadTop] = g[kHeadBase];
  for (const bool left : {true, false}) {
    const std::string s = left ? "left_" : "right_";
    const double sign = left ? 1.0 : -1.0;
    const int clavicle = left ? kLeftClavicle : kRightClavicle;
    const int shoulder = left ? kLeftShoulder : kRightShoulder;
    const int elbow = left ? kLeftElbow : kRightElbow;
    const int wrist = left ? kLeftWrist : kRightWrist;
    g[clavicle] = thorax * rot(Vector3d::UnitZ(), sign * channel(c, s + "clavicle_elevation")) *
                  rot(Vector3d::UnitY(), -sign * channel(c, s + "clavicle_protraction"));
    g[shoulder] = thorax * upper_arm_rotation(left, channel(c, s + "shoulder_elevation"),
                                              channel(c, s + "shoulder_plane"),
                                              channel(c, s + "shoulder_rotation"));
    g[elbow] = g[shoulder] * rot(Vector3d::UnitY(), -sign * channel(c, s + "elbow_flexion"));
    g[wrist] = g[elbow];
  }
  // Seated legs: thighs forward, shanks down, feet forward; they turn with the body.
  for (const int hip : {kLeftHip, kRightHip}) g[hip] = yaw * rot(Vector3d::UnitX(), -90.0);
  for (const int j : {kLeftKnee, kRightKnee, kLeftAnkle, kRightAnkle, kLeftToe, kRightToe}) {
    g[j] = yaw;
  }
  return g;
}

void check_channel_value(const ConfigNode& node, const std::string& channel_name, double value) {
  const ChannelLimits& limits = channel_limits().at(channel_name);
  if (!std::isfinite(value) || value < limits.min || value > limits.max) {
    char range[120];
    std::snprintf(range, sizeof(range), " = %g is outside its allowed range [%g, %g] degrees",
                  value, limits.min, limits.max);
    node.fail("channel '" + channel_name + "'" + range);
  }
}

// "both_x" names two channels; anything else must be a known channel name.
std::vector<std::string> expand_channel(const ConfigNode& node, const std::string& name) {
  std::vector<std::string> names;
  if (name.rfind("both_", 0) == 0) {
    names = {"left_" + name.substr(5), "right_" + name.substr(5)};
  } else {
    names = {name};
  }
  for (const std::string& n : names) {
    if (!channel_limits().count(n)) {
      node.fail("unknown channel '" + name + "' (see data/motions/README.md for the list)");
    }
  }
  return names;
}

}  // namespace

const std::vector<std::string>& library_activity_classes() {
  static const std::vector<std::string> classes = {"talking",          "wheelchair skills",
                                                   "daily routine",    "dance",
                                                   "basketball",       "tennis",
                                                   "extreme sports",   "general sports",
                                                   "household chores", "shopping",
                                                   "cooking",          "travel",
                                                   "photoshoot",       "rugby",
                                                   "pickleball",       "stretches",
                                                   "clapping",         "typing",
                                                   "dressing"};
  return classes;
}

const std::vector<std::string>& motion_channel_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> out;
    for (const auto& [name, limits] : channel_limits()) out.push_back(name);
    return out;
  }();
  return names;
}

MotionDefinition parse_motion_definition(const std::string& yaml_text, const std::string& origin) {
  const ConfigNode root = ConfigNode::load_string(yaml_text, origin);
  MotionDefinition motion;
  const ConfigNode id = root.child("id");
  motion.id = id.as_string();
  if (motion.id.empty() ||
      motion.id.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789_") != std::string::npos) {
    id.fail("id must be lower-case letters, digits and '_'");
  }
  if (origin.size() > 5 && origin.substr(origin.size() - 5) == ".yaml" &&
      file_stem(origin) != motion.id) {
    id.fail("id '" + motion.id + "' must equal the file name '" + file_stem(origin) + "'");
  }
  motion.activity_class = root.get_choice("class", "", library_activity_classes());
  if (motion.activity_class.empty()) root.child("class");  // reports the missing key
  motion.description = root.child("description").as_string();
  motion.duration = root.get_double("duration", 4.0, 0.5, 60.0);
  motion.fps = root.get_double("fps", 30.0, 1.0, 240.0);
  motion.loop = root.get_bool("loop", false);

  const ConfigNode keyframes = root.child("keyframes");
  if (!keyframes.is_sequence() || keyframes.size() == 0) {
    keyframes.fail("keyframes must be a non-empty list");
  }
  for (std::size_t i = 0; i < keyframes.size(); ++i) {
    const ConfigNode frame = keyframes.element(i);
    if (!frame.is_map()) frame.fail("a keyframe must be a map with 't' and channel values");
    const double t = frame.get_double("t", -1.0, 0.0, 1.0);
    if (t < 0.0) frame.child("t");
    for (const std::string& key : frame.keys()) {
      if (key == "t") continue;
      const ConfigNode value_node = frame.child(key);
      const double value = value_node.as_double();
      for (const std::string& name : expand_channel(value_node, key)) {
        check_channel_value(value_node, name, value);
        auto& keys = motion.tracks[name].keys;
        if (!keys.empty() && keys.back().first >= t) {
          frame.fail("keyframe times of channel '" + name + "' must increase");
        }
        keys.emplace_back(t, value);
      }
    }
    frame.finish();
  }
  if (motion.loop) {
    // A loop's t = 1 key repeats t = 0; it must agree and is then implied by the wrap-around.
    for (auto& [name, track] : motion.tracks) {
      if (track.keys.size() > 1 && track.keys.back().first == 1.0) {
        if (track.keys.front().first != 0.0 ||
            track.keys.front().second != track.keys.back().second) {
          keyframes.fail("looping motion: channel '" + name +
                         "' must have equal values at t=0 and t=1");
        }
        track.keys.pop_back();
      }
    }
  }

  if (const auto oscillators = root.optional_child("oscillators")) {
    if (!oscillators->is_sequence()) oscillators->fail("oscillators must be a list");
    for (std::size_t i = 0; i < oscillators->size(); ++i) {
      const ConfigNode node = oscillators->element(i);
      const ConfigNode channel_node = node.child("channel");
      Oscillator base;
      base.amplitude = node.get_double("amplitude", 0.0, 0.0, 90.0);
      base.cycles = node.get_double("cycles", 1.0, 0.0, 100.0);
      base.phase = node.get_double("phase", 0.0, -1.0, 1.0);
      base.start = node.get_double("start", 0.0, 0.0, 1.0);
      base.end = node.get_double("end", 1.0, 0.0, 1.0);
      if (base.end <= base.start) node.fail("oscillator 'end' must be after 'start'");
      if (motion.loop && base.start == 0.0 && base.end == 1.0 &&
          base.cycles != std::round(base.cycles)) {
        node.fail("an oscillator over a whole looping motion needs a whole number of cycles");
      }
      node.finish();
      for (const std::string& name : expand_channel(channel_node, channel_node.as_string())) {
        Oscillator osc = base;
        osc.channel = name;
        motion.oscillators.push_back(osc);
      }
    }
  }
  root.finish();
  return motion;
}

std::map<std::string, double> motion_channels_at(const MotionDefinition& motion, double t,
                                                 double amplitude) {
  std::map<std::string, double> values;
  for (const auto& [name, track] : motion.tracks) {
    double lo = track.keys.front().second;
    double hi = lo;
    for (const auto& key : track.keys) {
      lo = std::min(lo, key.second);
      hi = std::max(hi, key.second);
    }
    const double middle = 0.5 * (lo + hi);
    values[name] = middle + amplitude * (evaluate_track(track, t, motion.loop) - middle);
  }
  for (const Oscillator& osc : motion.oscillators) {
    values[osc.channel] += amplitude * oscillator_value(osc, t, motion.loop);
  }
  for (auto& [name, value] : values) {
    const ChannelLimits& limits = channel_limits().at(name);
    value = std::clamp(value, limits.min, limits.max);
  }
  return values;
}

Pose mirror_pose(const Pose& pose) {
  Pose out;
  for (int j = 0; j < kJointCount; ++j) {
    const Vector3d& p = pose[mirror_joint(j)];
    out[j] = Vector3d(-p.x(), p.y(), p.z());
  }
  return out;
}

PositionClip synthesize_motion(const MotionDefinition& motion, const MotionVariant& variant) {
  WHEELPOSE_CHECK(variant.speed > 0.0);
  const double duration = motion.duration / variant.speed;
  const int steps = std::max(2, static_cast<int>(std::lround(duration * motion.fps)));
  const int frame_count = motion.loop ? steps : steps + 1;

  SkeletalMotion skeletal;
  skeletal.name = motion.id;
  skeletal.fps = motion.fps;
  for (int j = 0; j < kJointCount; ++j) {
    skeletal.rest_offsets[j] = rest_direction(j) * default_bone_length(j);
  }
  for (int f = 0; f < frame_count; ++f) {
    const double t = static_cast<double>(f) / steps;
    const PoseRotations global = global_pose(motion_channels_at(motion, t, variant.amplitude));
    PoseRotations local;
    for (int j = 0; j < kJointCount; ++j) {
      const int parent = joint_parent(j);
      local[j] = parent < 0 ? global[j] : (global[parent].conjugate() * global[j]).normalized();
    }
    skeletal.local_rotations.push_back(local);
    skeletal.root_positions.emplace_back(0.0, 0.5, 0.0);
  }

  PositionClip clip;
  clip.name = motion.id;
  clip.source = "library:" + motion.id;
  clip.fps = motion.fps;
  clip.frames = forward_kinematics(skeletal);
  if (variant.mirrored) {
    for (Pose& pose : clip.frames) pose = mirror_pose(pose);
  }
  return clip;
}

MotionVariant library_variant(const std::string& id, std::uint64_t seed) {
  RandomStream stream(seed, {"library", std::string_view(id)});
  MotionVariant variant;
  variant.speed = stream.uniform(0.8, 1.25);
  variant.amplitude = stream.uniform(0.85, 1.1);
  variant.mirrored = stream.bernoulli(0.5);
  return variant;
}

std::vector<LibraryMotionInfo> library_motions() {
  std::vector<LibraryMotionInfo> out;
  for (const MotionDefinition& motion : loaded_library().motions) {
    out.push_back({motion.id, motion.activity_class, motion.description});
  }
  return out;
}

const MotionDefinition& library_definition(const std::string& id) { return find_motion(id); }

PositionClip library_clip(const std::string& id, std::uint64_t seed) {
  return synthesize_motion(find_motion(id), library_variant(id, seed));
}

std::vector<PositionClip> library_clips(std::uint64_t seed) {
  std::vector<PositionClip> out;
  for (const MotionDefinition& motion : loaded_library().motions) {
    out.push_back(synthesize_motion(motion, library_variant(motion.id, seed)));
  }
  return out;
}

}  // namespace wheelpose::motion
