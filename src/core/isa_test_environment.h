#pragma once
// For test binaries that the per-ISA CTest runs repeat (cmake: wheelpose_isa_tests): when
// WHEELPOSE_EMBREE_CONFIG asks for an ISA this CPU lacks, every test is skipped with a message
// saying so, instead of failing. Include it in one test file of the binary.

#include <gtest/gtest.h>

#include "core/cpu_isa.h"

namespace wheelpose::testing {

class IsaEnvironment : public ::testing::Environment {
 public:
  void SetUp() override {
    if (const std::string problem = isa_problem(); !problem.empty()) GTEST_SKIP() << problem;
  }
};

inline ::testing::Environment* const kIsaEnvironment =
    ::testing::AddGlobalTestEnvironment(new IsaEnvironment);

}  // namespace wheelpose::testing
