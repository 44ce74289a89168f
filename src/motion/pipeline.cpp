#include "motion/pipeline.h"

#include <spdlog/spdlog.h>

#include <cstring>
#include <sstream>

#include "core/error.h"
#include "motion/filter.h"
#include "motion/rotations.h"

namespace wheelpose::motion {

namespace {

// Each option's allowed range, held once: from_config reads with it (errors name file:line:key),
// check() applies it to options built in code.
struct Range {
  const char* name;
  double lo, hi;
};
constexpr Range kFilterOrder{"filter.order", 1, 8};
constexpr Range kFilterCutoff{"filter.cutoff_hz", 0.1, 100.0};
constexpr Range kThighElevation{"seat.thigh_elevation_deg", -30, 80};
constexpr Range kShinAngle{"seat.shin_angle_deg", -45, 60};
constexpr Range kFootPitch{"seat.foot_pitch_deg", -60, 60};
constexpr Range kNoiseAmplitude{"seat.noise_amplitude_deg", 0, 45};
constexpr Range kGapMean{"seat.keyframe_gap_mean", 0.01, 1.0};
constexpr Range kGapStddev{"seat.keyframe_gap_stddev", 0.0, 1.0};
constexpr Range kMinBone{"limits.min_bone_length", 0, 1};
constexpr Range kMaxBone{"limits.max_bone_length", 0.01, 10};
constexpr Range kMaxLengthChange{"limits.max_length_change", 0, 10};

// The key within its section ("order" of "filter.order").
const char* key(const Range& r) {
  const char* dot = std::strchr(r.name, '.');
  return dot ? dot + 1 : r.name;
}

void check_range(const Range& r, double value) {
  if (!(value >= r.lo && value <= r.hi)) {
    std::ostringstream text;
    text << "motion option " << r.name << " = " << value << " must be between " << r.lo << " and "
         << r.hi;
    throw Error(text.str(), ErrorKind::kBadInput);
  }
}

}  // namespace

void MotionOptions::check() const {
  check_range(kFilterOrder, filter_order);
  check_range(kFilterCutoff, filter_cutoff_hz);
  check_range(kThighElevation, seating.thigh_elevation_deg);
  check_range(kShinAngle, seating.shin_angle_deg);
  check_range(kFootPitch, seating.foot_pitch_deg);
  check_range(kNoiseAmplitude, seating.noise_amplitude_deg);
  check_range(kGapMean, seating.keyframe_gap_mean);
  check_range(kGapStddev, seating.keyframe_gap_stddev);
  check_range(kMinBone, limits.min_bone_length);
  check_range(kMaxBone, limits.max_bone_length);
  check_range(kMaxLengthChange, limits.max_length_change);
}

MotionOptions MotionOptions::from_config(const ConfigNode& node) {
  MotionOptions o;
  o.handedness =
      handedness_from_name(node.get_choice("handedness", "auto", {"auto", "standard", "mirrored"}));
  if (auto filter = node.optional_child("filter")) {
    o.filter = filter->get_bool("enabled", o.filter);
    o.filter_order = static_cast<int>(filter->get_int(key(kFilterOrder), o.filter_order,
                                                      static_cast<long long>(kFilterOrder.lo),
                                                      static_cast<long long>(kFilterOrder.hi)));
    auto read = [&](const Range& r, double value) {
      return filter->get_double(key(r), value, r.lo, r.hi);
    };
    o.filter_cutoff_hz = read(kFilterCutoff, o.filter_cutoff_hz);
    filter->finish();
  }
  if (auto seat = node.optional_child("seat")) {
    SeatingOptions& s = o.seating;
    auto read = [&](const Range& r, double value) {
      return seat->get_double(key(r), value, r.lo, r.hi);
    };
    o.seat = seat->get_bool("enabled", o.seat);
    s.thigh_elevation_deg = read(kThighElevation, s.thigh_elevation_deg);
    s.shin_angle_deg = read(kShinAngle, s.shin_angle_deg);
    s.foot_pitch_deg = read(kFootPitch, s.foot_pitch_deg);
    s.noise_amplitude_deg = read(kNoiseAmplitude, s.noise_amplitude_deg);
    s.keyframe_gap_mean = read(kGapMean, s.keyframe_gap_mean);
    s.keyframe_gap_stddev = read(kGapStddev, s.keyframe_gap_stddev);
    s.follow_heading = seat->get_bool("follow_heading", s.follow_heading);
    s.keep_root_translation = seat->get_bool("keep_root_translation", s.keep_root_translation);
    seat->finish();
  }
  if (auto limits = node.optional_child("limits")) {
    ClipLimits& l = o.limits;
    auto read = [&](const Range& r, double value) {
      return limits->get_double(key(r), value, r.lo, r.hi);
    };
    l.min_bone_length = read(kMinBone, l.min_bone_length);
    l.max_bone_length = read(kMaxBone, l.max_bone_length);
    l.max_length_change = read(kMaxLengthChange, l.max_length_change);
    limits->finish();
  }
  o.seed = static_cast<std::uint64_t>(node.get_int("seed", 0, 0, INT64_MAX));
  node.finish();
  return o;
}

nlohmann::ordered_json MotionOptions::to_json() const {
  const SeatingOptions& s = seating;
  return {
      {"handedness", handedness_name(handedness)},
      {"filter", {{"enabled", filter}, {"order", filter_order}, {"cutoff_hz", filter_cutoff_hz}}},
      {"seat",
       {{"enabled", seat},
        {"thigh_elevation_deg", s.thigh_elevation_deg},
        {"shin_angle_deg", s.shin_angle_deg},
        {"foot_pitch_deg", s.foot_pitch_deg},
        {"noise_amplitude_deg", s.noise_amplitude_deg},
        {"keyframe_gap_mean", s.keyframe_gap_mean},
        {"keyframe_gap_stddev", s.keyframe_gap_stddev},
        {"follow_heading", s.follow_heading},
        {"keep_root_translation", s.keep_root_translation}}},
      {"limits",
       {{"min_bone_length", limits.min_bone_length},
        {"max_bone_length", limits.max_bone_length},
        {"max_length_change", limits.max_length_change}}},
      {"seed", seed}};
}

void make_rotations_continuous(SkeletalMotion& motion) {
  for (std::size_t f = 1; f < motion.local_rotations.size(); ++f) {
    for (int j = 0; j < kJointCount; ++j) {
      Eigen::Quaterniond& q = motion.local_rotations[f][j];
      if (q.dot(motion.local_rotations[f - 1][j]) < 0) q.coeffs() = -q.coeffs();
    }
  }
}

SeatedClip run_motion_pipeline(const PositionClip& clip, const MotionOptions& options) {
  options.check();
  ClipLimits limits = options.limits;
  std::optional<FilterCoefficients> filter;
  std::string filter_note = "disabled";
  if (options.filter) {
    if (options.filter_cutoff_hz < clip.fps / 2) {
      filter = butterworth_lowpass(options.filter_order, options.filter_cutoff_hz, clip.fps);
      limits.min_frames = std::max(limits.min_frames, filtfilt_padding(*filter) + 1);
      filter_note = "applied";
    } else {
      // At or below twice the cutoff there is nothing above the cutoff left to remove.
      filter_note = "skipped: cutoff is at or above the Nyquist frequency";
    }
  }
  validate_position_clip(clip, limits);

  std::vector<Pose> frames = clip.frames;
  const Handedness handedness =
      options.handedness == Handedness::kAuto && !clip.handedness_uncertain ? Handedness::kStandard
                                                                            : options.handedness;
  const OrientationResult orientation = normalize_orientation(frames, handedness);
  if (filter) lowpass_positions(frames, *filter);

  SeatedClip seated;
  seated.motion = solve_rotations(frames, clip.fps, clip.name);
  if (options.seat) {
    const RandomStream stream(options.seed, {"motion", "seat", clip.name});
    seat_legs(seated.motion, options.seating, stream, filter ? &*filter : nullptr);
  }
  make_rotations_continuous(seated.motion);
  seated.positions = forward_kinematics(seated.motion);

  seated.provenance = {
      {"source", clip.source},
      {"source_fps", clip.fps},
      {"source_frames", clip.frames.size()},
      {"mirrored", orientation.mirrored},
      {"yaw_applied_deg", orientation.yaw_radians * 180.0 / M_PI},
      {"filter", filter_note},
      {"parameters", options.to_json()},
  };
  spdlog::debug("{}: {} frames at {} fps, mirrored={}, filter {}", clip.name, clip.frames.size(),
                clip.fps, orientation.mirrored, filter_note);
  return seated;
}

}  // namespace wheelpose::motion
