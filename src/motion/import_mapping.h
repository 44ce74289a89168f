#pragma once
// Joint-name mappings used by the importers: how each of our 23 joints is obtained from the named
// points of a source (BVH joints, keypoint landmarks). A mapping is data — adding a rig or a
// keypoint layout means adding one table entry.

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "motion/clip.h"

namespace wheelpose::motion {

// One named source point with its weight. A joint is an affine combination of source points
// (weights sum to 1): {"Hips", 1} copies a joint, {"A", .5}, {"B", .5} is the midpoint.
struct MappingTerm {
  std::string source;
  double weight = 1.0;
};
using JointRecipe = std::vector<MappingTerm>;

struct ImportMapping {
  std::string name;
  double unit_scale = 1.0;                             // metres per source unit
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();  // source axes -> ours, after scaling
  // Per joint: alternatives; the first whose source points are all present is used.
  std::array<std::vector<JointRecipe>, kJointCount> joints;
  // Source names the format may contain; empty = any (names not used by the recipes are ignored).
  std::vector<std::string> known_sources;
};

// A mapping resolved against the source points of one file: per joint, (index, weight) pairs.
struct ResolvedMapping {
  std::array<std::vector<std::pair<int, double>>, kJointCount> joints;
  double scale = 1.0;
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();
};

// Resolves `mapping` against the names present in a file. Throws wheelpose::Error naming `where`,
// the joint and the missing source name(s) if no alternative of some joint is available.
// `unit_scale` overrides the mapping's scale when > 0.
ResolvedMapping resolve_mapping(const ImportMapping& mapping, const std::vector<std::string>& names,
                                double unit_scale, const std::string& where);

// Our 23 joints from the source points (in the order of the names given to resolve_mapping).
Pose apply_mapping(const ResolvedMapping& mapping, const std::vector<Eigen::Vector3d>& points);

// Helpers for writing tables.
JointRecipe recipe_from(const std::string& a);
JointRecipe recipe_mean(const std::string& a, const std::string& b);

}  // namespace wheelpose::motion
