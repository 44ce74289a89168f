#pragma once
// The process's one Embree device (devices are thread-safe; creating one per frame cost
// milliseconds and its memory pools). It is configured from WHEELPOSE_EMBREE_CONFIG, Embree's
// own config string (isa=sse4.2|avx|avx2|avx512, threads=N, verbose=N, ...), and every error
// Embree reports goes through one callback, so a bad CPU, config or scene becomes one clear
// wheelpose::Error instead of a crash or a silently empty image.

#include <embree3/rtcore.h>

#include <string>

namespace wheelpose::render {

// The shared device, created on first use. Throws Error when the CPU lacks SSE4.2, the config
// asks for an ISA the CPU does not have, or Embree refuses the config. The caller retains it.
RTCDevice shared_embree_device();

// Throws Error(kFailure) naming `during` and Embree's message when Embree has reported an error
// on the shared device since the last check (from any thread); clears it.
void throw_on_embree_error(const std::string& during);

}  // namespace wheelpose::render
