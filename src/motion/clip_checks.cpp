#include "motion/clip_checks.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/error.h"

namespace wheelpose::motion {

namespace {

[[noreturn]] void reject(const PositionClip& clip, const std::string& reason) {
  throw Error((clip.source.empty() ? clip.name : clip.source) + ": " + reason);
}

std::string bone_name(int joint) {
  return std::string(joint_name(joint_parent(joint))) + "->" + std::string(joint_name(joint));
}

std::string metres(double value) {
  std::ostringstream out;
  out.precision(3);
  out << value << " m";
  return out.str();
}

}  // namespace

void validate_position_clip(const PositionClip& clip, const ClipLimits& limits) {
  if (!(clip.fps > 0) || !std::isfinite(clip.fps)) reject(clip, "frame rate must be positive");
  if (static_cast<int>(clip.frames.size()) < limits.min_frames) {
    reject(clip, "has " + std::to_string(clip.frames.size()) + " frames; at least " +
                     std::to_string(limits.min_frames) + " are needed (filter padding)");
  }
  for (std::size_t f = 0; f < clip.frames.size(); ++f) {
    for (int j = 0; j < kJointCount; ++j) {
      if (!clip.frames[f][j].allFinite()) {
        reject(clip, "frame " + std::to_string(f) + " joint " + std::string(joint_name(j)) +
                         " is not a finite number");
      }
    }
  }
  std::vector<double> lengths(clip.frames.size());
  for (int j = 0; j < kJointCount; ++j) {
    if (joint_parent(j) < 0) continue;
    for (std::size_t f = 0; f < clip.frames.size(); ++f) {
      lengths[f] = (clip.frames[f][j] - clip.frames[f][joint_parent(j)]).norm();
    }
    std::vector<double> sorted = lengths;
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    const double median = sorted[sorted.size() / 2];
    if (median < limits.min_bone_length) {
      reject(clip, "bone " + bone_name(j) + " is collapsed (median length " + metres(median) + ")");
    }
    const double tolerance = limits.max_length_change * median + limits.length_change_slack;
    for (std::size_t f = 0; f < lengths.size(); ++f) {
      if (lengths[f] > limits.max_bone_length) {
        reject(clip, "bone " + bone_name(j) + " explodes to " + metres(lengths[f]) + " at frame " +
                         std::to_string(f));
      }
      if (std::abs(lengths[f] - median) > tolerance) {
        reject(clip, "bone " + bone_name(j) + " changes length from " + metres(median) + " to " +
                         metres(lengths[f]) + " at frame " + std::to_string(f));
      }
    }
  }
}

}  // namespace wheelpose::motion
