#include "learn/data_parallel.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <future>

#include "core/error.h"

namespace wheelpose::learn {
namespace {

namespace fs = std::filesystem;

// Two ranks (threads here, processes in use) meet at a file store; after average() both hold
// the mean of their gradients and loss parts.
TEST(GradientAverager, TwoRanksHoldTheMeanOfTheirGradients) {
  const fs::path store = fs::temp_directory_path() / "wheelpose_gradient_averager_store";
  fs::remove(store);
  auto rank = [&](int r) {
    GradientAverager averager("file://" + store.string(), r, 2);
    torch::Tensor a = torch::zeros({2}, torch::requires_grad());
    torch::Tensor b = torch::zeros({2, 2}, torch::requires_grad());
    a.mutable_grad() = torch::tensor({1.0f + 2 * r, 2.0f + 2 * r});
    b.mutable_grad() = torch::full({2, 2}, r == 0 ? 4.0f : 0.0f);
    StepReport parts;
    parts.loss = 1 + 2 * r;
    parts.box_offset = 10 * r;
    averager.average({a, b}, parts);
    averager.barrier();
    return std::make_tuple(a.grad().clone(), b.grad().clone(), parts);
  };
  auto zero = std::async(std::launch::async, rank, 0);
  auto one = std::async(std::launch::async, rank, 1);
  const auto [a0, b0, p0] = zero.get();
  const auto [a1, b1, p1] = one.get();
  EXPECT_TRUE(torch::equal(a0, torch::tensor({2.0f, 3.0f})));
  EXPECT_TRUE(torch::equal(a1, torch::tensor({2.0f, 3.0f})));
  EXPECT_TRUE(torch::equal(b0, torch::full({2, 2}, 2.0f)));  // (4 + 0) / 2
  EXPECT_TRUE(torch::equal(b1, torch::full({2, 2}, 2.0f)));
  EXPECT_DOUBLE_EQ(p0.loss, 2.0);
  EXPECT_DOUBLE_EQ(p1.loss, 2.0);
  EXPECT_DOUBLE_EQ(p0.box_offset, 5.0);
  fs::remove(store);
}

TEST(GradientAverager, MalformedRendezvousIsNamed) {
  try {
    GradientAverager("udp://x", 0, 2);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("udp://x"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace wheelpose::learn
