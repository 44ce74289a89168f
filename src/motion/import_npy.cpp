#include "motion/import_npy.h"

#include <cmath>

#include "core/error.h"
#include "motion/import_mapping.h"
#include "motion/npy.h"

namespace wheelpose::motion {

namespace {

constexpr double kHumanMl3dFps = 20.0;

// SMPL-22 -> our joints (reference §1.1): spine1/2/3 -> spine/chest/upper_chest, feet (balls of
// the feet) -> toes, collars -> clavicles, SMPL neck -> head_base, SMPL head -> head_top, and the
// neck base is the mean of the collars unless the file carries it (23-joint arrays).
const ImportMapping& smpl22_mapping() {
  static const ImportMapping mapping = [] {
    ImportMapping m;
    m.name = "smpl22";
    auto set = [&](Joint j, const std::string& source) { m.joints[j] = {recipe_from(source)}; };
    set(kPelvis, "pelvis");
    set(kLeftHip, "left_hip");
    set(kRightHip, "right_hip");
    set(kSpine, "spine1");
    set(kLeftKnee, "left_knee");
    set(kRightKnee, "right_knee");
    set(kChest, "spine2");
    set(kLeftAnkle, "left_ankle");
    set(kRightAnkle, "right_ankle");
    set(kUpperChest, "spine3");
    set(kLeftToe, "left_foot");
    set(kRightToe, "right_foot");
    set(kHeadBase, "neck");
    set(kLeftClavicle, "left_collar");
    set(kRightClavicle, "right_collar");
    set(kHeadTop, "head");
    set(kLeftShoulder, "left_shoulder");
    set(kRightShoulder, "right_shoulder");
    set(kLeftElbow, "left_elbow");
    set(kRightElbow, "right_elbow");
    set(kLeftWrist, "left_wrist");
    set(kRightWrist, "right_wrist");
    m.joints[kNeckBase] = {recipe_from("neck_base"), recipe_mean("left_collar", "right_collar")};
    return m;
  }();
  return mapping;
}

}  // namespace

const std::vector<std::string>& smpl22_joint_names() {
  static const std::vector<std::string> names = {
      "pelvis",     "left_hip",    "right_hip",    "spine1",      "left_knee",     "right_knee",
      "spine2",     "left_ankle",  "right_ankle",  "spine3",      "left_foot",     "right_foot",
      "neck",       "left_collar", "right_collar", "head",        "left_shoulder", "right_shoulder",
      "left_elbow", "right_elbow", "left_wrist",   "right_wrist", "neck_base"};
  return names;
}

PositionClip import_npy(const std::filesystem::path& path, const ImportOptions& options) {
  const std::string where = path.string();
  NpyArray array = read_npy(path);
  const auto& shape = array.shape;
  auto shape_text = [&] {
    std::string s = "(";
    for (std::size_t i = 0; i < shape.size(); ++i) s += (i ? ", " : "") + std::to_string(shape[i]);
    return s + (shape.size() == 1 ? ",)" : ")");
  };
  if (shape.size() != 3 || (shape[1] != 22 && shape[1] != 23) || shape[2] != 3) {
    throw Error(where + ": array shape " + shape_text() +
                " is not (frames, 22, 3) or (frames, 23, 3) joint positions");
  }
  if (shape[0] == 0) throw Error(where + ": the array has no frames");
  if (!options.mapping.empty() && options.mapping != "smpl22") {
    throw Error(where + ": unknown mapping '" + options.mapping + "' for .npy (only smpl22)");
  }
  const std::size_t frames = shape[0];
  const std::size_t joints = shape[1];
  std::vector<std::string> names(smpl22_joint_names().begin(),
                                 smpl22_joint_names().begin() + static_cast<long>(joints));
  ResolvedMapping mapping = resolve_mapping(smpl22_mapping(), names, options.unit_scale, where);

  PositionClip clip;
  clip.name = path.stem().string();
  clip.source = where;
  clip.fps = options.fps > 0 ? options.fps : kHumanMl3dFps;
  clip.handedness_uncertain = true;  // HumanML3D mixes mirrored (HumanAct12) and standard data
  clip.frames.reserve(frames);
  std::vector<Eigen::Vector3d> points(joints);
  for (std::size_t t = 0; t < frames; ++t) {
    for (std::size_t j = 0; j < joints; ++j) {
      const double* v = &array.values[(t * joints + j) * 3];
      if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2])) {
        throw Error(where + ": frame " + std::to_string(t) + ", joint " + std::to_string(j) + " (" +
                    names[j] + ") is not finite");
      }
      points[j] = Eigen::Vector3d(v[0], v[1], v[2]);
    }
    clip.frames.push_back(apply_mapping(mapping, points));
  }
  return clip;
}

}  // namespace wheelpose::motion
