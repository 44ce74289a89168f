#pragma once
// Process-wide heap tuning for programs that render frame after frame.

namespace wheelpose {

// Keeps freed frame-sized blocks (image buffers, post-processing temporaries; up to 32 MiB each)
// in the heap for the next frame instead of returning them to the kernel. By default glibc maps
// each such block afresh and unmaps it on free, so every frame page-faults and zero-fills tens of
// megabytes again (≈ 7 % of a 1280×720 render). Memory stays bounded by the largest frame's
// working set. Call once at the start of main(); returns false if glibc refused a setting.
bool retain_freed_memory();

// Also keeps blocks larger than 32 MiB in the heap (no mmap at all). For programs whose working
// set repeats per item with blocks above glibc's 32 MiB cap, such as a pose model at 512 px
// (two 36 MiB activations per image: mapping and zero-filling them afresh costs 165 → 48 ms per
// image). Call after retain_freed_memory(); returns false if glibc refused.
bool retain_large_blocks();

}  // namespace wheelpose
