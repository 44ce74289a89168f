#pragma once
// FBX time: integer ticks of 1/46186158000 s, and the GlobalSettings TimeMode of a frame rate.
// Key times are computed with integers from the frame index and the rate as an exact fraction
// (30000/1001 for 29.97...), so a key never lands a tick early as one from seconds in floating
// point can.

#include <cstdint>

namespace wheelpose::motion {

inline constexpr std::int64_t kFbxTicksPerSecond = 46186158000;

// TimeMode entries (FbxTime::EMode) of the fixed rates.
inline constexpr int kFbxTimeModeCustom = 14;

// A rate as numerator / denominator: the fraction with the smallest denominator (up to 10^6)
// equal to `fps` within 1e-12 relative, else the closest one found. Throws Error (bad input)
// for rates outside [kMinFrameRate, kMaxFrameRate], NaN included.
inline constexpr double kMinFrameRate = 1e-3;
inline constexpr double kMaxFrameRate = 1e6;
struct FrameRate {
  std::int64_t numerator;
  std::int64_t denominator;
};
FrameRate exact_frame_rate(double fps);

// Tick of `frame` at `rate`: frame · 46186158000 · denominator / numerator, rounded to the
// nearest tick (halves up).
std::int64_t fbx_frame_time(std::int64_t frame, const FrameRate& rate);

// The TimeMode whose rate equals `rate` exactly (120 → 1, 100 → 2, 60 → 3, 50 → 4, 48 → 5,
// 30 → 6, 30000/1001 → 9, 25 → 10, 24 → 11, 1000 → 12, 24000/1001 → 13, 96 → 15, 72 → 16,
// 60000/1001 → 17, 120000/1001 → 18), else kFbxTimeModeCustom (the rate then goes in
// CustomFrameRate).
int fbx_time_mode(const FrameRate& rate);

}  // namespace wheelpose::motion
