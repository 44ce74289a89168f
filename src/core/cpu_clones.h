#pragma once
// AVX2 copies of hot loops, chosen at run time. Write the loop once as a WHEELPOSE_LOOP_BODY
// function, and WHEELPOSE_AVX2_COPY(name, body) defines name(...) that runs an AVX2 build of it
// when use_avx2_loops() says so and the baseline (SSE2) build otherwise. Only for loops whose
// lanes are independent: AVX2 without FMA computes each lane as the baseline does, so both give
// the same bits. Because the choice follows active_isa(), WHEELPOSE_EMBREE_CONFIG=isa=sse4.2
// runs the baseline copies on any CPU, and the per-ISA tests check that both agree.

#include "core/cpu_isa.h"

#define WHEELPOSE_LOOP_BODY inline __attribute__((always_inline))

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define WHEELPOSE_AVX2_COPY(name, body)                            \
  template <typename... Args>                                      \
  __attribute__((target("avx2"))) void name##_avx2(Args... args) { \
    body(args...);                                                 \
  }                                                                \
  template <typename... Args>                                      \
  void name(Args... args) {                                        \
    if (::wheelpose::use_avx2_loops()) {                           \
      name##_avx2(args...);                                        \
    } else {                                                       \
      body(args...);                                               \
    }                                                              \
  }
#else
#define WHEELPOSE_AVX2_COPY(name, body) \
  template <typename... Args>           \
  void name(Args... args) {             \
    body(args...);                      \
  }
#endif

namespace wheelpose {

// True when active_isa() is AVX2 or higher (false if it cannot render at all). Cached.
bool use_avx2_loops() noexcept;

}  // namespace wheelpose
