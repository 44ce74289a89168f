#pragma once
// WHEELPOSE_AVX2_CLONE before a function compiles it twice, for AVX2 and for the baseline, and
// picks one when the program loads (GCC/Clang function multiversioning on x86-64 glibc). Only
// for loops whose lanes are independent: AVX2 without FMA computes each lane as the baseline
// does, so both clones give the same bits. Elsewhere it expands to nothing.
#if defined(__x86_64__) && defined(__linux__) && (defined(__GNUC__) || defined(__clang__))
#define WHEELPOSE_AVX2_CLONE __attribute__((target_clones("avx2", "default")))
#else
#define WHEELPOSE_AVX2_CLONE
#endif
