#include "motion/import_mapping.h"

#include <algorithm>

#include "core/error.h"

namespace wheelpose::motion {

ResolvedMapping resolve_mapping(const ImportMapping& mapping, const std::vector<std::string>& names,
                                double unit_scale, const std::string& where) {
  auto index_of = [&](const std::string& name) -> int {
    auto it = std::find(names.begin(), names.end(), name);
    return it == names.end() ? -1 : static_cast<int>(it - names.begin());
  };
  ResolvedMapping resolved;
  resolved.scale = unit_scale > 0 ? unit_scale : mapping.unit_scale;
  resolved.axes = mapping.axes;
  for (int j = 0; j < kJointCount; ++j) {
    const auto& alternatives = mapping.joints[j];
    WHEELPOSE_CHECK(!alternatives.empty());
    std::string first_missing;
    bool done = false;
    for (const JointRecipe& recipe : alternatives) {
      std::vector<std::pair<int, double>> terms;
      for (const MappingTerm& term : recipe) {
        int index = index_of(term.source);
        if (index < 0) {
          if (first_missing.empty()) first_missing = term.source;
          terms.clear();
          break;
        }
        terms.emplace_back(index, term.weight);
      }
      if (!terms.empty()) {
        resolved.joints[j] = std::move(terms);
        done = true;
        break;
      }
    }
    if (!done) {
      throw Error(where + ": joint '" + first_missing + "' (needed for " +
                  std::string(joint_name(j)) + " by mapping '" + mapping.name + "') is missing");
    }
  }
  return resolved;
}

Pose apply_mapping(const ResolvedMapping& mapping, const std::vector<Eigen::Vector3d>& points) {
  Pose pose;
  for (int j = 0; j < kJointCount; ++j) {
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    for (const auto& [index, weight] : mapping.joints[j]) p += weight * points[index];
    pose[j] = mapping.axes * (mapping.scale * p);
  }
  return pose;
}

JointRecipe recipe_from(const std::string& a) { return {{a, 1.0}}; }

JointRecipe recipe_mean(const std::string& a, const std::string& b) { return {{a, 0.5}, {b, 0.5}}; }

}  // namespace wheelpose::motion
