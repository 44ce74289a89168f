#include "motion/import_bvh.h"

#include <Eigen/Geometry>
#include <charconv>
#include <cmath>
#include <numbers>

#include "core/atomic_file.h"
#include "core/error.h"

namespace wheelpose::motion {

namespace {

// CMU motion-capture units: the ASF skeletons declare `length 0.45`, i.e. one unit is
// 1/0.45 inch = 0.05644 m. Checked on 131_0x.bvh: thigh 7.29 units = 0.41 m, shin 6.92 = 0.39 m.
constexpr double kCmuMetresPerUnit = 0.0254 / 0.45;

struct Token {
  std::string_view text;
  int line;
};

// Splits `text` into whitespace-separated tokens with 1-based line numbers.
std::vector<Token> tokenize_line(std::string_view line, int number) {
  std::vector<Token> tokens;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    std::size_t start = i;
    while (i < line.size() && !std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    if (i > start) tokens.push_back({line.substr(start, i - start), number});
  }
  return tokens;
}

std::vector<std::string_view> split_lines(std::string_view text) {
  std::vector<std::string_view> lines;
  std::size_t start = 0;
  while (start <= text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(start, end - start);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    lines.push_back(line);
    start = end + 1;
  }
  return lines;
}

class Parser {
 public:
  Parser(std::string_view text, const std::string& where) : where_(where) {
    lines_ = split_lines(text);
  }

  BvhMotion parse() {
    // Tokens of the hierarchy section: everything before the MOTION line.
    std::size_t motion_line = lines_.size();
    for (std::size_t i = 0; i < lines_.size(); ++i) {
      auto tokens = tokenize_line(lines_[i], static_cast<int>(i + 1));
      if (!tokens.empty() && tokens[0].text == "MOTION") {
        motion_line = i;
        break;
      }
      tokens_.insert(tokens_.end(), tokens.begin(), tokens.end());
    }
    if (tokens_.empty() || tokens_[0].text != "HIERARCHY")
      fail(1, "file does not start with HIERARCHY");
    pos_ = 1;
    while (pos_ < tokens_.size()) {
      Token t = next("ROOT");
      if (t.text != "ROOT") fail(t.line, "expected ROOT, found '" + std::string(t.text) + "'");
      parse_joint(-1);
    }
    if (motion_.joints.empty()) fail(static_cast<int>(lines_.size()), "no ROOT joint");
    if (motion_line == lines_.size()) {
      fail(static_cast<int>(lines_.size()), "no MOTION section (truncated file?)");
    }
    parse_motion(motion_line + 1);
    return std::move(motion_);
  }

 private:
  [[noreturn]] void fail(int line, const std::string& what) const {
    throw Error(where_ + ":" + std::to_string(line) + ": " + what);
  }

  Token next(const char* expected) {
    if (pos_ >= tokens_.size()) {
      int line = tokens_.empty() ? 1 : tokens_.back().line;
      fail(line, std::string("unexpected end of hierarchy, expected ") + expected);
    }
    return tokens_[pos_++];
  }

  void expect(std::string_view text) {
    Token t = next(std::string(text).c_str());
    if (t.text != text) {
      fail(t.line, "expected '" + std::string(text) + "', found '" + std::string(t.text) + "'");
    }
  }

  double number(std::string_view text, int line) const {
    return number(text, line, [] { return std::string(); });
  }

  // `context` describes the value (frame, joint, channel) for the error message.
  template <typename Context>
  double number(std::string_view text, int line, Context context) const {
    std::string_view digits = text;
    if (!digits.empty() && digits[0] == '+') digits.remove_prefix(1);
    double value = 0;
    auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
    if (ec != std::errc() || end != digits.data() + digits.size()) {
      fail(line, "'" + std::string(text) + "' is not a number" + context());
    }
    if (!std::isfinite(value)) {
      fail(line, "'" + std::string(text) + "' is not a finite number" + context());
    }
    return value;
  }

  // " (frame F, joint J, channel C)" for value `k` of the frame line being read.
  std::string channel_context(std::size_t k) const {
    static constexpr const char* kChannelNames[] = {"Xposition", "Yposition", "Zposition",
                                                    "Xrotation", "Yrotation", "Zrotation"};
    for (const BvhJoint& joint : motion_.joints) {
      auto first = static_cast<std::size_t>(joint.first_channel);
      if (!joint.channels.empty() && k >= first && k < first + joint.channels.size()) {
        return " (frame " + std::to_string(motion_.frames.size()) + ", joint " + joint.name +
               ", channel " + kChannelNames[static_cast<int>(joint.channels[k - first])] + ")";
      }
    }
    return "";
  }

  Eigen::Vector3d parse_offset() {
    expect("OFFSET");
    Eigen::Vector3d v;
    for (int i = 0; i < 3; ++i) {
      Token t = next("an OFFSET value");
      v[i] = number(t.text, t.line);
    }
    return v;
  }

  void parse_joint(int parent) {
    Token name = next("a joint name");
    BvhJoint joint;
    joint.name = std::string(name.text);
    joint.parent = parent;
    int index = static_cast<int>(motion_.joints.size());
    motion_.joints.push_back(joint);
    expect("{");
    bool have_offset = false;
    while (true) {
      Token t = next("'}'");
      if (t.text == "}") break;
      if (t.text == "OFFSET") {
        --pos_;
        motion_.joints[index].offset = parse_offset();
        have_offset = true;
      } else if (t.text == "CHANNELS") {
        Token n = next("a channel count");
        double count = number(n.text, n.line);
        if (count < 0 || count > 6 || count != std::floor(count)) {
          fail(n.line, "CHANNELS count must be 0..6, found '" + std::string(n.text) + "'");
        }
        auto& joint_ref = motion_.joints[index];
        joint_ref.first_channel = motion_.channel_count;
        for (int i = 0; i < static_cast<int>(count); ++i) {
          Token c = next("a channel name");
          joint_ref.channels.push_back(channel(c));
        }
        motion_.channel_count += static_cast<int>(count);
      } else if (t.text == "JOINT") {
        parse_joint(index);
      } else if (t.text == "End") {
        expect("Site");
        BvhJoint end;
        end.name = motion_.joints[index].name + ".end";
        end.parent = index;
        end.end_site = true;
        expect("{");
        end.offset = parse_offset();
        expect("}");
        motion_.joints.push_back(end);
      } else {
        fail(t.line, "unexpected '" + std::string(t.text) + "' in joint '" +
                         motion_.joints[index].name + "'");
      }
    }
    if (!have_offset) fail(name.line, "joint '" + std::string(name.text) + "' has no OFFSET");
  }

  BvhChannel channel(const Token& t) const {
    static const std::pair<std::string_view, BvhChannel> kNames[] = {
        {"Xposition", BvhChannel::kXposition}, {"Yposition", BvhChannel::kYposition},
        {"Zposition", BvhChannel::kZposition}, {"Xrotation", BvhChannel::kXrotation},
        {"Yrotation", BvhChannel::kYrotation}, {"Zrotation", BvhChannel::kZrotation}};
    for (const auto& [name, value] : kNames) {
      if (t.text == name) return value;
    }
    fail(t.line, "unknown channel '" + std::string(t.text) + "'");
  }

  // "Frames: N", "Frame Time: t", then one line of channel values per frame.
  void parse_motion(std::size_t first) {
    std::size_t i = first;
    auto next_nonblank = [&]() -> std::vector<Token> {
      while (i < lines_.size()) {
        auto tokens = tokenize_line(lines_[i], static_cast<int>(i + 1));
        ++i;
        if (!tokens.empty()) return tokens;
      }
      fail(static_cast<int>(lines_.size()), "truncated MOTION section (no Frames/Frame Time)");
    };
    auto frames_line = next_nonblank();
    if (frames_line.size() != 2 || frames_line[0].text != "Frames:") {
      fail(frames_line[0].line, "expected 'Frames: <count>'");
    }
    double frames = number(frames_line[1].text, frames_line[1].line);
    if (frames < 1 || frames != std::floor(frames)) {
      fail(frames_line[1].line, "frame count must be a positive integer");
    }
    auto time_line = next_nonblank();
    if (time_line.size() != 3 || time_line[0].text != "Frame" || time_line[1].text != "Time:") {
      fail(time_line[0].line, "expected 'Frame Time: <seconds>'");
    }
    motion_.frame_time = number(time_line[2].text, time_line[2].line);
    if (motion_.frame_time <= 0) fail(time_line[2].line, "Frame Time must be positive");

    const auto expected = static_cast<std::size_t>(frames);
    for (; i < lines_.size(); ++i) {
      int line = static_cast<int>(i + 1);
      auto tokens = tokenize_line(lines_[i], line);
      if (tokens.empty()) continue;
      if (motion_.frames.size() == expected) {
        fail(line, "more frame lines than 'Frames: " + std::to_string(expected) + "'");
      }
      if (static_cast<int>(tokens.size()) != motion_.channel_count) {
        fail(line, std::to_string(tokens.size()) + " values on a frame line, expected " +
                       std::to_string(motion_.channel_count) + " (one per channel)");
      }
      std::vector<double> values(tokens.size());
      for (std::size_t k = 0; k < tokens.size(); ++k) {
        values[k] = number(tokens[k].text, line, [&] { return channel_context(k); });
      }
      motion_.frames.push_back(std::move(values));
    }
    if (motion_.frames.size() < expected) {
      fail(static_cast<int>(lines_.size()),
           "truncated MOTION section: 'Frames: " + std::to_string(expected) + "' but only " +
               std::to_string(motion_.frames.size()) + " frame lines");
    }
  }

  const std::string& where_;
  std::vector<std::string_view> lines_;
  std::vector<Token> tokens_;
  std::size_t pos_ = 0;
  BvhMotion motion_;
};

// Table rows: our joint and its recipe over BVH joint names ("X.end" = end site of X).
using RigRow = std::pair<Joint, JointRecipe>;

ImportMapping make_rig(const std::string& name, double scale, const std::vector<RigRow>& rows) {
  ImportMapping m;
  m.name = name;
  m.unit_scale = scale;
  for (const auto& [joint, recipe] : rows) m.joints[joint] = {recipe};
  for (int j = 0; j < kJointCount; ++j) WHEELPOSE_CHECK(!m.joints[j].empty());
  return m;
}

JointRecipe recipe_quarter(const char* a, const char* b, const char* c, const char* d) {
  return {{a, .25}, {b, .25}, {c, .25}, {d, .25}};
}

}  // namespace

BvhMotion parse_bvh(std::string_view text, const std::string& where) {
  return Parser(text, where).parse();
}

std::vector<Eigen::Vector3d> bvh_global_positions(const BvhMotion& motion, std::size_t frame) {
  const std::vector<double>& values = motion.frames.at(frame);
  const std::size_t n = motion.joints.size();
  std::vector<Eigen::Vector3d> positions(n);
  std::vector<Eigen::Matrix3d> rotations(n);
  for (std::size_t j = 0; j < n; ++j) {
    const BvhJoint& joint = motion.joints[j];
    Eigen::Vector3d translation = joint.offset;
    Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
    for (std::size_t c = 0; c < joint.channels.size(); ++c) {
      double v = values[static_cast<std::size_t>(joint.first_channel) + c];
      double radians = v * std::numbers::pi / 180.0;
      switch (joint.channels[c]) {
        case BvhChannel::kXposition:
          translation.x() = v;
          break;
        case BvhChannel::kYposition:
          translation.y() = v;
          break;
        case BvhChannel::kZposition:
          translation.z() = v;
          break;
        case BvhChannel::kXrotation:
          rotation = rotation * Eigen::AngleAxisd(radians, Eigen::Vector3d::UnitX());
          break;
        case BvhChannel::kYrotation:
          rotation = rotation * Eigen::AngleAxisd(radians, Eigen::Vector3d::UnitY());
          break;
        case BvhChannel::kZrotation:
          rotation = rotation * Eigen::AngleAxisd(radians, Eigen::Vector3d::UnitZ());
          break;
      }
    }
    if (joint.parent < 0) {
      positions[j] = translation;
      rotations[j] = rotation;
    } else {
      const auto p = static_cast<std::size_t>(joint.parent);
      positions[j] = positions[p] + rotations[p] * translation;
      rotations[j] = rotations[p] * rotation;
    }
  }
  return positions;
}

// Rig tables. Both CMU rigs: the clavicle point is halfway along the collar bone (collar joint ->
// shoulder joint), the neck base is the mean of the two clavicle points, the chest lies halfway
// between the two spine joints, head_base is the upper-neck joint and head_top the end site of
// the head (top of the skull).
const std::vector<ImportMapping>& bvh_rigs() {
  static const std::vector<ImportMapping> rigs = {
      // CMU data as converted in bvh11 / the shared 131_0x.bvh files.
      make_rig("cmu", kCmuMetresPerUnit,
               {{kPelvis, recipe_from("Hips")},
                {kLeftHip, recipe_from("LeftHip")},
                {kRightHip, recipe_from("RightHip")},
                {kLeftKnee, recipe_from("LeftKnee")},
                {kRightKnee, recipe_from("RightKnee")},
                {kLeftAnkle, recipe_from("LeftAnkle")},
                {kRightAnkle, recipe_from("RightAnkle")},
                {kLeftToe, recipe_from("LeftToe")},
                {kRightToe, recipe_from("RightToe")},
                {kSpine, recipe_from("Chest")},
                {kChest, recipe_mean("Chest", "Chest2")},
                {kUpperChest, recipe_from("Chest2")},
                {kNeckBase,
                 recipe_quarter("LeftCollar", "LeftShoulder", "RightCollar", "RightShoulder")},
                {kLeftClavicle, recipe_mean("LeftCollar", "LeftShoulder")},
                {kRightClavicle, recipe_mean("RightCollar", "RightShoulder")},
                {kHeadBase, recipe_from("Neck")},
                {kHeadTop, recipe_from("Head.end")},
                {kLeftShoulder, recipe_from("LeftShoulder")},
                {kRightShoulder, recipe_from("RightShoulder")},
                {kLeftElbow, recipe_from("LeftElbow")},
                {kRightElbow, recipe_from("RightElbow")},
                {kLeftWrist, recipe_from("LeftWrist")},
                {kRightWrist, recipe_from("RightWrist")}}),
      // CMU data as converted for MotionBuilder (cgspeed names).
      make_rig("cmu_mb", kCmuMetresPerUnit,
               {{kPelvis, recipe_from("Hips")},
                {kLeftHip, recipe_from("LeftUpLeg")},
                {kRightHip, recipe_from("RightUpLeg")},
                {kLeftKnee, recipe_from("LeftLeg")},
                {kRightKnee, recipe_from("RightLeg")},
                {kLeftAnkle, recipe_from("LeftFoot")},
                {kRightAnkle, recipe_from("RightFoot")},
                {kLeftToe, recipe_from("LeftToeBase")},
                {kRightToe, recipe_from("RightToeBase")},
                {kSpine, recipe_from("Spine")},
                {kChest, recipe_mean("Spine", "Spine1")},
                {kUpperChest, recipe_from("Spine1")},
                {kNeckBase, recipe_quarter("LeftShoulder", "LeftArm", "RightShoulder", "RightArm")},
                {kLeftClavicle, recipe_mean("LeftShoulder", "LeftArm")},
                {kRightClavicle, recipe_mean("RightShoulder", "RightArm")},
                {kHeadBase, recipe_from("Neck1")},
                {kHeadTop, recipe_from("Head.end")},
                {kLeftShoulder, recipe_from("LeftArm")},
                {kRightShoulder, recipe_from("RightArm")},
                {kLeftElbow, recipe_from("LeftForeArm")},
                {kRightElbow, recipe_from("RightForeArm")},
                {kLeftWrist, recipe_from("LeftHand")},
                {kRightWrist, recipe_from("RightHand")}}),
  };
  return rigs;
}

double bvh_frame_rate(double frame_time) {
  const double fps = 1.0 / frame_time;
  for (double rate : {std::round(fps), std::round(fps * 1.001) * 1000.0 / 1001.0}) {
    if (rate > 0 && std::abs(fps - rate) <= 1e-4 * fps) return rate;
  }
  return fps;
}

PositionClip import_bvh(const std::filesystem::path& path, const ImportOptions& options) {
  const std::string where = path.string();
  BvhMotion motion = parse_bvh(read_file(path), where);
  std::vector<std::string> names;
  names.reserve(motion.joints.size());
  for (const BvhJoint& joint : motion.joints) names.push_back(joint.name);

  ResolvedMapping mapping;
  const auto& rigs = bvh_rigs();
  if (options.mapping.empty()) {
    // Default "cmu"; the other built-in rigs are tried in order when its joint names are absent.
    std::string first_error;
    bool found = false;
    for (std::size_t r = 0; r < rigs.size() && !found; ++r) {
      try {
        mapping = resolve_mapping(rigs[r], names, options.unit_scale, where);
        found = true;
      } catch (const Error& e) {
        if (first_error.empty()) first_error = e.what();
      }
    }
    if (!found) throw Error(first_error + " (no built-in BVH rig matches this file)");
  } else {
    const ImportMapping* rig = nullptr;
    std::string known;
    for (const ImportMapping& r : rigs) {
      if (r.name == options.mapping) rig = &r;
      known += (known.empty() ? "" : ", ") + r.name;
    }
    if (rig == nullptr) {
      throw Error(where + ": unknown BVH mapping '" + options.mapping + "' (built in: " + known +
                  ")");
    }
    mapping = resolve_mapping(*rig, names, options.unit_scale, where);
  }

  PositionClip clip;
  clip.name = path.stem().string();
  clip.source = where;
  clip.fps = options.fps > 0 ? options.fps : bvh_frame_rate(motion.frame_time);
  clip.frames.reserve(motion.frames.size());
  for (std::size_t f = 0; f < motion.frames.size(); ++f) {
    clip.frames.push_back(apply_mapping(mapping, bvh_global_positions(motion, f)));
  }
  return clip;
}

}  // namespace wheelpose::motion
