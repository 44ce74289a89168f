#include "motion/fbx_time.h"

#include <cmath>
#include <string>

#include "core/error.h"

namespace wheelpose::motion {

FrameRate exact_frame_rate(double fps) {
  if (!(fps >= kMinFrameRate && fps <= kMaxFrameRate)) {
    throw Error("frame rate " + std::to_string(fps) + " is outside what FBX time can hold (" +
                std::to_string(kMinFrameRate) + " to " + std::to_string(kMaxFrameRate) + " fps)");
  }
  // Continued fraction of fps: convergents h/k.
  std::int64_t h_prev = 1, h = static_cast<std::int64_t>(std::floor(fps));
  std::int64_t k_prev = 0, k = 1;
  double rest = fps - std::floor(fps);
  for (int step = 0; step < 40; ++step) {
    if (std::abs(static_cast<double>(h) / static_cast<double>(k) - fps) <= 1e-12 * fps) break;
    if (rest <= 0) break;
    const double inverse = 1.0 / rest;
    const auto a = static_cast<std::int64_t>(std::floor(inverse));
    rest = inverse - std::floor(inverse);
    const std::int64_t h_next = a * h + h_prev, k_next = a * k + k_prev;
    if (k_next > 1000000) break;
    h_prev = h;
    k_prev = k;
    h = h_next;
    k = k_next;
  }
  return {h, k};
}

std::int64_t fbx_frame_time(std::int64_t frame, const FrameRate& rate) {
  WHEELPOSE_CHECK(frame >= 0 && rate.numerator > 0 && rate.denominator > 0);
  const __int128 scaled = static_cast<__int128>(frame) * kFbxTicksPerSecond * rate.denominator;
  return static_cast<std::int64_t>((2 * scaled + rate.numerator) / (2 * rate.numerator));
}

int fbx_time_mode(const FrameRate& rate) {
  struct Mode {
    std::int64_t numerator, denominator;
    int mode;
  };
  static constexpr Mode kModes[] = {
      {120, 1, 1},       {100, 1, 2},      {60, 1, 3},  {50, 1, 4},        {48, 1, 5},
      {30, 1, 6},        {30000, 1001, 9}, {25, 1, 10}, {24, 1, 11},       {1000, 1, 12},
      {24000, 1001, 13}, {96, 1, 15},      {72, 1, 16}, {60000, 1001, 17}, {120000, 1001, 18},
  };
  for (const Mode& m : kModes) {
    if (m.numerator * rate.denominator == rate.numerator * m.denominator) return m.mode;
  }
  return kFbxTimeModeCustom;
}

}  // namespace wheelpose::motion
