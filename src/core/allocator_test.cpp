#include "core/allocator.h"

#include <gtest/gtest.h>
#include <malloc.h>

#include <cstdlib>
#include <cstring>

namespace wheelpose {
namespace {

// After the call, a freed frame-sized block goes back to the heap, not to the kernel: glibc's
// mallinfo2 counts mmapped bytes (hblkhd) apart from heap bytes.
TEST(Allocator, FrameSizedBlocksComeFromTheHeapAfterTuning) {
  ASSERT_TRUE(retain_freed_memory());
  constexpr std::size_t kFrame = 11u << 20;  // a 1280×720 float RGB image
  const std::size_t mapped_before = mallinfo2().hblkhd;
  void* block = std::malloc(kFrame);
  ASSERT_NE(block, nullptr);
  std::memset(block, 1, kFrame);
  EXPECT_EQ(mallinfo2().hblkhd, mapped_before);  // not a fresh mapping
  std::free(block);
  const std::size_t heap_free = mallinfo2().fordblks;
  EXPECT_GE(heap_free, kFrame);  // kept for reuse, not trimmed
}

}  // namespace
}  // namespace wheelpose
