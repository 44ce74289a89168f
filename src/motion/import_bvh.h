#pragma once
// BVH (Biovision hierarchy) motion: any hierarchy and channel order. Joint positions come from
// forward kinematics of the channels; a per-rig mapping table turns the rig's joints into ours.

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "motion/clip.h"
#include "motion/import_mapping.h"
#include "motion/importers.h"

namespace wheelpose::motion {

enum class BvhChannel { kXposition, kYposition, kZposition, kXrotation, kYrotation, kZrotation };

struct BvhJoint {
  std::string name;  // end sites are named "<parent name>.end"
  int parent = -1;
  bool end_site = false;
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  std::vector<BvhChannel> channels;
  int first_channel = 0;  // index of this joint's first value in a frame line
};

struct BvhMotion {
  std::vector<BvhJoint> joints;  // parents precede children
  int channel_count = 0;
  double frame_time = 0;                    // seconds
  std::vector<std::vector<double>> frames;  // channel_count values per frame
};

// Parses BVH text; `where` names the source in errors (with line numbers).
BvhMotion parse_bvh(std::string_view text, const std::string& where);

// Global positions (source units) of every joint and end site in one frame, in the order of
// motion.joints. Position channels replace the joint's OFFSET (the value is its full local
// translation); rotation channels compose in the listed order, R = R1 * R2 * R3, in degrees.
std::vector<Eigen::Vector3d> bvh_global_positions(const BvhMotion& motion, std::size_t frame);

// Built-in rigs ("cmu", "cmu_mb"), in the order tried when no mapping is named.
const std::vector<ImportMapping>& bvh_rigs();

PositionClip import_bvh(const std::filesystem::path& path, const ImportOptions& options);

// The clip rate of a Frame Time. Files print it rounded (CMU: .0083333 for 1/120 s), so a rate
// within 0.01 % of a whole number, or of an NTSC n·1000/1001, is taken as exactly that.
double bvh_frame_rate(double frame_time);

}  // namespace wheelpose::motion
