#pragma once
// Shared fixture for body tests: the model is loaded once per test binary.

#include "body/person.h"

namespace wheelpose::body::testing {

inline const BodyData& body_data() {
  static const BodyData data(std::filesystem::path(WHEELPOSE_SHARED_DIR) / "assets");
  return data;
}

}  // namespace wheelpose::body::testing
