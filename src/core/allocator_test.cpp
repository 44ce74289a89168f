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

// With large blocks retained too, a block above glibc's 32 MiB mmap cap is heap memory as well.
// Runs last in this file: the setting is process-wide.
TEST(Allocator, LargeBlocksComeFromTheHeapWhenRetained) {
  ASSERT_TRUE(retain_freed_memory());
  ASSERT_TRUE(retain_large_blocks());
  constexpr std::size_t kActivation = 36u << 20;  // multipose at 512 px
  const std::size_t mapped_before = mallinfo2().hblkhd;
  void* block = std::malloc(kActivation);
  ASSERT_NE(block, nullptr);
  std::memset(block, 1, kActivation);
  EXPECT_EQ(mallinfo2().hblkhd, mapped_before);
  std::free(block);
  EXPECT_GE(mallinfo2().fordblks, kActivation);
}

}  // namespace
}  // namespace wheelpose
