#include "core/allocator.h"

#include <malloc.h>

namespace wheelpose {

bool retain_freed_memory() {
  // glibc caps the mmap threshold at 32 MiB on 64-bit; a fixed value also stops it from
  // adapting (and from moving the trim threshold with it).
  constexpr int kMmapThreshold = 32 << 20;
  constexpr int kTrimThreshold = 1 << 30;  // free heap top kept up to 1 GiB
  bool ok = mallopt(M_MMAP_THRESHOLD, kMmapThreshold) == 1;
  ok = mallopt(M_TRIM_THRESHOLD, kTrimThreshold) == 1 && ok;
  return ok;
}

bool retain_large_blocks() { return mallopt(M_MMAP_MAX, 0) == 1; }

}  // namespace wheelpose
