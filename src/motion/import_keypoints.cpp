#include "motion/import_keypoints.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>

#include "core/atomic_file.h"
#include "core/error.h"

namespace wheelpose::motion {

namespace {

constexpr double kDefaultKeypointFps = 30.0;

const std::vector<std::string> kBlazePoseNames = {
    "nose",        "left_eye_inner",  "left_eye",        "left_eye_outer", "right_eye_inner",
    "right_eye",   "right_eye_outer", "left_ear",        "right_ear",      "mouth_left",
    "mouth_right", "left_shoulder",   "right_shoulder",  "left_elbow",     "right_elbow",
    "left_wrist",  "right_wrist",     "left_pinky",      "right_pinky",    "left_index",
    "right_index", "left_thumb",      "right_thumb",     "left_hip",       "right_hip",
    "left_knee",   "right_knee",      "left_ankle",      "right_ankle",    "left_heel",
    "right_heel",  "left_foot_index", "right_foot_index"};

ImportMapping wheelpose23_mapping() {
  ImportMapping m;
  m.name = "wheelpose23";
  for (int j = 0; j < kJointCount; ++j) {
    m.joints[j] = {recipe_from(std::string(joint_name(j)))};
    m.known_sources.emplace_back(joint_name(j));
  }
  // The neck base may be left out: it is the mean of the clavicles (reference §1.1).
  m.joints[kNeckBase].push_back(recipe_mean("left_clavicle", "right_clavicle"));
  return m;
}

// MediaPipe world landmarks: metres, origin between the hips, x to the image's right, y down,
// z away from the camera. Turning that frame 180 degrees about X (y, z negated) gives +Y up with a
// subject facing the camera facing +Z and their left at +X; negating y alone would mirror.
// Joints BlazePose lacks are affine combinations of H = mid-hips, S = mid-shoulders,
// E = mid-ears: the trunk H..S is split in quarters (spine, chest, upper chest, neck base = S),
// clavicles lie 20% of the way from S to each shoulder, head_base = (S + E) / 2 and
// head_top = E + (E - head_base); toes are the foot_index landmarks.
ImportMapping blazepose33_mapping() {
  ImportMapping m;
  m.name = "blazepose33";
  m.axes = Eigen::Vector3d(1, -1, -1).asDiagonal();
  m.known_sources = kBlazePoseNames;
  auto set = [&](Joint j, JointRecipe recipe) { m.joints[j] = {std::move(recipe)}; };
  const char* lh = "left_hip";
  const char* rh = "right_hip";
  const char* ls = "left_shoulder";
  const char* rs = "right_shoulder";
  const char* le = "left_ear";
  const char* re = "right_ear";
  set(kPelvis, recipe_mean(lh, rh));
  set(kLeftHip, recipe_from(lh));
  set(kRightHip, recipe_from(rh));
  set(kSpine, {{lh, .375}, {rh, .375}, {ls, .125}, {rs, .125}});
  set(kChest, {{lh, .25}, {rh, .25}, {ls, .25}, {rs, .25}});
  set(kUpperChest, {{lh, .125}, {rh, .125}, {ls, .375}, {rs, .375}});
  set(kNeckBase, recipe_mean(ls, rs));
  set(kLeftClavicle, {{ls, .6}, {rs, .4}});
  set(kRightClavicle, {{rs, .6}, {ls, .4}});
  set(kHeadBase, {{ls, .25}, {rs, .25}, {le, .25}, {re, .25}});
  set(kHeadTop, {{le, .75}, {re, .75}, {ls, -.25}, {rs, -.25}});
  set(kLeftShoulder, recipe_from(ls));
  set(kRightShoulder, recipe_from(rs));
  set(kLeftElbow, recipe_from("left_elbow"));
  set(kRightElbow, recipe_from("right_elbow"));
  set(kLeftWrist, recipe_from("left_wrist"));
  set(kRightWrist, recipe_from("right_wrist"));
  set(kLeftKnee, recipe_from("left_knee"));
  set(kRightKnee, recipe_from("right_knee"));
  set(kLeftAnkle, recipe_from("left_ankle"));
  set(kRightAnkle, recipe_from("right_ankle"));
  set(kLeftToe, recipe_from("left_foot_index"));
  set(kRightToe, recipe_from("right_foot_index"));
  return m;
}

const ImportMapping& find_mapping(const std::string& name, const std::string& where) {
  const std::string wanted = name.empty() ? "wheelpose23" : name;
  std::string known;
  for (const ImportMapping& m : keypoint_mappings()) {
    if (m.name == wanted) return m;
    known += (known.empty() ? "" : ", ") + m.name;
  }
  throw Error(where + ": unknown keypoint mapping '" + wanted + "' (built in: " + known + ")");
}

bool is_known(const ImportMapping& mapping, const std::string& name) {
  return std::find(mapping.known_sources.begin(), mapping.known_sources.end(), name) !=
         mapping.known_sources.end();
}

std::string unknown_joint(const ImportMapping& mapping, const std::string& name) {
  return "unknown joint '" + name + "' for mapping '" + mapping.name + "'";
}

// Keypoints as read, before mapping.
struct RawSequence {
  std::vector<std::string> names;
  std::vector<std::vector<Eigen::Vector3d>> frames;  // frames x names
  std::optional<double> fps;
};

PositionClip finish(const std::filesystem::path& path, const ImportOptions& options,
                    const ImportMapping& mapping, const RawSequence& raw) {
  const std::string where = path.string();
  if (raw.frames.empty()) throw Error(where + ": no frames");
  ResolvedMapping resolved = resolve_mapping(mapping, raw.names, options.unit_scale, where);
  PositionClip clip;
  clip.name = path.stem().string();
  clip.source = where;
  clip.fps = options.fps > 0 ? options.fps : raw.fps.value_or(kDefaultKeypointFps);
  clip.frames.reserve(raw.frames.size());
  for (const auto& points : raw.frames) clip.frames.push_back(apply_mapping(resolved, points));
  return clip;
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

std::vector<std::string_view> split_csv(std::string_view line) {
  std::vector<std::string_view> cells;
  std::size_t start = 0;
  while (true) {
    std::size_t comma = line.find(',', start);
    cells.push_back(
        trim(line.substr(start, comma == std::string_view::npos ? comma : comma - start)));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return cells;
}

// A CSV cell as a finite number; `context` says which frame/joint it belongs to.
double csv_number(std::string_view cell, const std::string& at, const std::string& context) {
  std::string_view text = cell;
  if (!text.empty() && text[0] == '+') text.remove_prefix(1);
  double value = 0;
  auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || ec != std::errc() || end != text.data() + text.size()) {
    throw Error(at + ": '" + std::string(cell) + "' is not a number (" + context + ")");
  }
  if (!std::isfinite(value)) {
    throw Error(at + ": '" + std::string(cell) + "' is not a finite number (" + context + ")");
  }
  return value;
}

long csv_frame(std::string_view cell, const std::string& at) {
  long value = -1;
  auto [end, ec] = std::from_chars(cell.data(), cell.data() + cell.size(), value);
  if (cell.empty() || ec != std::errc() || end != cell.data() + cell.size() || value < 0) {
    throw Error(at + ": frame '" + std::string(cell) + "' is not a non-negative integer");
  }
  return value;
}

}  // namespace

const std::vector<ImportMapping>& keypoint_mappings() {
  static const std::vector<ImportMapping> mappings = {wheelpose23_mapping(), blazepose33_mapping()};
  return mappings;
}

namespace {

// A keypoint CSV read line by line: "# fps" comments, the header (long form
// "frame,joint,x,y,z" or wide form "frame,<joint>_x,<joint>_y,<joint>_z,..."), then rows.
class CsvKeypoints {
 public:
  CsvKeypoints(std::string where, const ImportMapping& mapping)
      : where_(std::move(where)), mapping_(mapping) {}

  void add_line(std::string_view line, int line_number) {
    const std::string at = where_ + ":" + std::to_string(line_number);
    if (line.empty()) return;
    if (line[0] == '#') return read_comment(line, at);
    std::vector<std::string_view> cells = split_csv(line);
    if (header_.empty()) return read_header(std::move(cells), at, line_number);
    if (cells.size() != header_.size()) {
      throw Error(at + ": " + std::to_string(cells.size()) + " values, expected " +
                  std::to_string(header_.size()) + " (as in the header on line " +
                  std::to_string(header_line_) + ")");
    }
    const long frame = csv_frame(cells[0], at);
    if (wide_) {
      add_wide_row(cells, frame, at);
    } else {
      add_long_row(cells, frame, at, line_number);
    }
  }

  // The frames read; throws for a file without a header or a long form with gaps.
  RawSequence finish() {
    if (header_.empty()) throw Error(where_ + ": empty CSV file (no header)");
    if (!wide_) long_rows_to_frames();
    return std::move(raw_);
  }

 private:
  // "# fps: 30" or "# fps = 30"; other comments are ignored.
  void read_comment(std::string_view line, const std::string& at) {
    std::string_view body = trim(line.substr(1));
    if (body.substr(0, 3) != "fps") return;
    body = trim(body.substr(3));
    if (!body.empty() && (body[0] == ':' || body[0] == '=')) body = trim(body.substr(1));
    double fps = csv_number(body, at, "fps");
    if (fps <= 0) throw Error(at + ": fps must be positive");
    raw_.fps = fps;
  }

  void read_header(std::vector<std::string_view> cells, const std::string& at, int line_number) {
    header_ = std::move(cells);
    header_line_ = line_number;
    if (header_.size() == 5 && header_[0] == "frame" && header_[1] == "joint" &&
        header_[2] == "x" && header_[3] == "y" && header_[4] == "z") {
      return;
    }
    wide_ = true;
    if (header_[0] != "frame" || header_.size() < 4 || (header_.size() - 1) % 3 != 0) {
      throw Error(at + ": header must be 'frame,joint,x,y,z' or 'frame,<joint>_x,<joint>_y," +
                  "<joint>_z,...'");
    }
    for (std::size_t c = 1; c < header_.size(); c += 3) {
      std::string_view col = header_[c];
      if (col.size() < 3 || col.substr(col.size() - 2) != "_x") {
        throw Error(at + ": column " + std::to_string(c + 1) + " '" + std::string(col) +
                    "' should be '<joint>_x'");
      }
      std::string name(col.substr(0, col.size() - 2));
      if (header_[c + 1] != name + "_y" || header_[c + 2] != name + "_z") {
        throw Error(at + ": columns after '" + std::string(col) + "' should be '" + name + "_y," +
                    name + "_z'");
      }
      if (!is_known(mapping_, name)) throw Error(at + ": " + unknown_joint(mapping_, name));
      if (std::find(raw_.names.begin(), raw_.names.end(), name) != raw_.names.end()) {
        throw Error(at + ": joint '" + name + "' appears twice in the header");
      }
      raw_.names.push_back(name);
    }
  }

  // Wide form: one frame per row, in order.
  void add_wide_row(const std::vector<std::string_view>& cells, long frame, const std::string& at) {
    if (last_frame_ && frame != *last_frame_ + 1) {
      throw Error(at + ": frame " + std::to_string(frame) + " follows frame " +
                  std::to_string(*last_frame_) + " (frames must be consecutive)");
    }
    last_frame_ = frame;
    std::vector<Eigen::Vector3d> points(raw_.names.size());
    for (std::size_t k = 0; k < raw_.names.size(); ++k) {
      std::string context = "frame " + std::to_string(frame) + ", joint " + raw_.names[k];
      for (int a = 0; a < 3; ++a) points[k][a] = csv_number(cells[1 + 3 * k + a], at, context);
    }
    raw_.frames.push_back(std::move(points));
  }

  // Long form: one joint per row, collected per frame number.
  void add_long_row(const std::vector<std::string_view>& cells, long frame, const std::string& at,
                    int line_number) {
    std::string name(cells[1]);
    if (!is_known(mapping_, name)) throw Error(at + ": " + unknown_joint(mapping_, name));
    std::string context = "frame " + std::to_string(frame) + ", joint " + name;
    Eigen::Vector3d p;
    for (int a = 0; a < 3; ++a) p[a] = csv_number(cells[2 + a], at, context);
    auto& frame_rows = long_rows_[frame];
    if (frame_rows.contains(name)) {
      throw Error(at + ": joint '" + name + "' appears twice in frame " + std::to_string(frame) +
                  " (first on line " + std::to_string(frame_rows[name].second) + ")");
    }
    frame_rows[name] = {p, line_number};
    if (std::find(raw_.names.begin(), raw_.names.end(), name) == raw_.names.end()) {
      raw_.names.push_back(name);
    }
  }

  void long_rows_to_frames() {
    std::optional<long> previous;
    for (const auto& [frame, rows] : long_rows_) {
      if (previous && frame != *previous + 1) {
        throw Error(where_ + ": frame " + std::to_string(*previous + 1) +
                    " has no rows (frames must be consecutive)");
      }
      previous = frame;
      std::vector<Eigen::Vector3d> points(raw_.names.size());
      for (std::size_t k = 0; k < raw_.names.size(); ++k) {
        auto it = rows.find(raw_.names[k]);
        if (it == rows.end()) {
          throw Error(where_ + ": frame " + std::to_string(frame) + " has no row for joint '" +
                      raw_.names[k] + "' (other frames have one)");
        }
        points[k] = it->second.first;
      }
      raw_.frames.push_back(std::move(points));
    }
  }

  const std::string where_;
  const ImportMapping& mapping_;
  RawSequence raw_;
  std::vector<std::string_view> header_;
  int header_line_ = 0;
  bool wide_ = false;
  std::optional<long> last_frame_;  // wide form
  // Long form: per frame number, each joint's point and line.
  std::map<long, std::map<std::string, std::pair<Eigen::Vector3d, int>>> long_rows_;
};

}  // namespace

PositionClip import_keypoints_csv(const std::filesystem::path& path, const ImportOptions& options) {
  const std::string where = path.string();
  const ImportMapping& mapping = find_mapping(options.mapping, where);
  std::string text = read_file(path);
  // Spreadsheet programs may start a UTF-8 CSV with a byte-order mark.
  if (text.starts_with("\xEF\xBB\xBF")) text.erase(0, 3);
  CsvKeypoints csv(where, mapping);
  std::size_t start = 0;
  int line_number = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    csv.add_line(trim(std::string_view(text).substr(start, end - start)), ++line_number);
    start = end + 1;
  }
  return finish(path, options, mapping, csv.finish());
}

PositionClip import_keypoints_json(const std::filesystem::path& path,
                                   const ImportOptions& options) {
  const std::string where = path.string();
  const ImportMapping& mapping = find_mapping(options.mapping, where);
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(read_file(path));
  } catch (const nlohmann::json::parse_error& e) {
    throw Error(where + ": not valid JSON: " + e.what());
  }
  if (!doc.is_object()) throw Error(where + ": top level must be an object");
  RawSequence raw;
  if (doc.contains("fps")) {
    const auto& fps = doc["fps"];
    if (!fps.is_number() || fps.get<double>() <= 0) {
      throw Error(where + ": 'fps' must be a positive number");
    }
    raw.fps = fps.get<double>();
  }
  if (!doc.contains("joints") || !doc["joints"].is_array()) {
    throw Error(where + ": needs a 'joints' array of joint names");
  }
  if (!doc.contains("frames") || !doc["frames"].is_array()) {
    throw Error(where + ": needs a 'frames' array");
  }
  const auto& joints = doc["joints"];
  for (std::size_t k = 0; k < joints.size(); ++k) {
    const std::string at = where + ": joints[" + std::to_string(k) + "]";
    if (!joints[k].is_string()) throw Error(at + ": must be a string");
    std::string name = joints[k].get<std::string>();
    if (!is_known(mapping, name)) throw Error(at + ": " + unknown_joint(mapping, name));
    if (std::find(raw.names.begin(), raw.names.end(), name) != raw.names.end()) {
      throw Error(at + ": joint '" + name + "' is listed twice");
    }
    raw.names.push_back(name);
  }
  const auto& frames = doc["frames"];
  for (std::size_t f = 0; f < frames.size(); ++f) {
    const std::string at = where + ": frames[" + std::to_string(f) + "]";
    const auto& frame = frames[f];
    if (!frame.is_array() || frame.size() != raw.names.size()) {
      throw Error(
          at + ": expected an array of " + std::to_string(raw.names.size()) +
          " points (one per entry of 'joints'), found " +
          (frame.is_array() ? std::to_string(frame.size()) + " entries" : frame.type_name()));
    }
    std::vector<Eigen::Vector3d> points(raw.names.size());
    for (std::size_t k = 0; k < raw.names.size(); ++k) {
      const auto& p = frame[k];
      const std::string point_at = at + "[" + std::to_string(k) + "] (" + raw.names[k] + ")";
      if (!p.is_array() || p.size() != 3) throw Error(point_at + ": expected [x, y, z]");
      for (int a = 0; a < 3; ++a) {
        if (!p[a].is_number()) {
          throw Error(point_at + ": coordinate " + std::to_string(a) + " is " + p[a].dump() +
                      ", not a number");
        }
        points[k][a] = p[a].get<double>();
        if (!std::isfinite(points[k][a])) throw Error(point_at + ": coordinate is not finite");
      }
    }
    raw.frames.push_back(std::move(points));
  }
  return finish(path, options, mapping, raw);
}

}  // namespace wheelpose::motion
