#pragma once
// Shared fixture for body tests: the model, loaded once per test binary, and point-list
// distances.

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "body/person.h"

namespace wheelpose::body::testing {

inline const BodyData& body_data() {
  static const BodyData data(std::filesystem::path(WHEELPOSE_SHARED_DIR) / "assets");
  return data;
}

// Largest distance between corresponding points (the lists must be as long).
inline float max_distance(const std::vector<Eigen::Vector3f>& a,
                          const std::vector<Eigen::Vector3f>& b) {
  EXPECT_EQ(a.size(), b.size());
  float worst = 0;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i)
    worst = std::max(worst, (a[i] - b[i]).norm());
  return worst;
}

// Mean distance between corresponding points.
inline float mean_distance(const std::vector<Eigen::Vector3f>& a,
                           const std::vector<Eigen::Vector3f>& b) {
  double sum = 0;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) sum += (a[i] - b[i]).norm();
  return static_cast<float>(sum / static_cast<double>(std::max<std::size_t>(a.size(), 1)));
}

}  // namespace wheelpose::body::testing
