#include "motion/fbx_time.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/error.h"

namespace wheelpose::motion {
namespace {

TEST(FbxTime, RatesBecomeExactFractions) {
  const auto expect_rate = [](double fps, std::int64_t numerator, std::int64_t denominator) {
    const FrameRate rate = exact_frame_rate(fps);
    EXPECT_EQ(rate.numerator, numerator) << fps;
    EXPECT_EQ(rate.denominator, denominator) << fps;
  };
  expect_rate(30, 30, 1);
  expect_rate(120, 120, 1);
  expect_rate(20, 20, 1);
  expect_rate(30000.0 / 1001.0, 30000, 1001);
  expect_rate(24000.0 / 1001.0, 24000, 1001);
  expect_rate(29.97, 2997, 100);
  expect_rate(12.5, 25, 2);
  expect_rate(0.5, 1, 2);
}

TEST(FbxTime, KeyTimesAreExactTicks) {
  EXPECT_EQ(fbx_frame_time(0, exact_frame_rate(30)), 0);
  EXPECT_EQ(fbx_frame_time(1, exact_frame_rate(30)), 1539538600);
  EXPECT_EQ(fbx_frame_time(117, exact_frame_rate(30)), 117 * std::int64_t{1539538600});
  EXPECT_EQ(fbx_frame_time(1, exact_frame_rate(120)), 384884650);
  EXPECT_EQ(fbx_frame_time(1, exact_frame_rate(20)), 2309307900);
  // 3.9 s at 30 fps and 8.275 s at 120 fps, the spans the ASCII export used to cut to 3 s and 8 s.
  EXPECT_EQ(fbx_frame_time(117, exact_frame_rate(30)), 180126016200);   // 3.9 s
  EXPECT_EQ(fbx_frame_time(993, exact_frame_rate(120)), 382190457450);  // 8.275 s
  // 29.97 fps: 1001/30000 s = 1541078138.6 ticks, rounded to the nearest tick each time.
  const FrameRate ntsc = exact_frame_rate(30000.0 / 1001.0);
  EXPECT_EQ(fbx_frame_time(1, ntsc), 1541078139);
  EXPECT_EQ(fbx_frame_time(2, ntsc), 3082156277);
  EXPECT_EQ(fbx_frame_time(30000, ntsc), 1001 * kFbxTicksPerSecond);
}

TEST(FbxTime, NoKeyIsEarlyOrLateByHalfATickOrMore) {
  // Exact reference in long double from integers: frame · ticks/s · denominator / numerator.
  for (double fps : {20.0, 24.0, 25.0, 30.0, 50.0, 60.0, 100.0, 120.0, 29.97, 30000.0 / 1001.0,
                     12.5, 7.0, 33.0, 240.0}) {
    const FrameRate rate = exact_frame_rate(fps);
    for (std::int64_t frame = 0; frame < 5000; frame += 7) {
      const long double exact =
          static_cast<long double>(frame) * kFbxTicksPerSecond * rate.denominator / rate.numerator;
      const std::int64_t ticks = fbx_frame_time(frame, rate);
      EXPECT_LE(std::abs(static_cast<long double>(ticks) - exact), 0.5L) << fps << " " << frame;
    }
  }
}

TEST(FbxTime, TimeModesFollowTheFbxEnum) {
  EXPECT_EQ(fbx_time_mode(exact_frame_rate(120)), 1);
  EXPECT_EQ(fbx_time_mode(exact_frame_rate(100)), 2);
  EXPECT_EQ(fbx_time_mode(exact_frame_rate(60)), 3);
  EXPECT_EQ(fbx_time_mode(exact_frame_rate(50)), 4);
  EXPECT_EQ(fbx_time_mode(exact_frame_rate(48)), 5);
  EXPECT_EQ(fbx_time_mode(exact_frame_rate(30)), 6);
  EXPECT_EQ(fbx_time_mode(exact_frame_rate(30000.0 / 1001.0)), 9);
  EXPECT_EQ(fbx_time_mode(exact_frame_rate(25)), 10);
  EXPECT_EQ(fbx_time_mode(exact_frame_rate(24)), 11);
  EXPECT_EQ(fbx_time_mode(exact_frame_rate(1000)), 12);
  EXPECT_EQ(fbx_time_mode(exact_frame_rate(24000.0 / 1001.0)), 13);
  EXPECT_EQ(fbx_time_mode(exact_frame_rate(96)), 15);
  EXPECT_EQ(fbx_time_mode(exact_frame_rate(72)), 16);
  EXPECT_EQ(fbx_time_mode(exact_frame_rate(60000.0 / 1001.0)), 17);
  EXPECT_EQ(fbx_time_mode(exact_frame_rate(120000.0 / 1001.0)), 18);
  // No enum entry: custom.
  EXPECT_EQ(fbx_time_mode(exact_frame_rate(20)), kFbxTimeModeCustom);
  EXPECT_EQ(fbx_time_mode(exact_frame_rate(29.97)), kFbxTimeModeCustom);
  EXPECT_EQ(fbx_time_mode(exact_frame_rate(120.0048)), kFbxTimeModeCustom);
}

TEST(FbxTime, RejectsRatesFbxCannotHold) {
  for (double fps :
       {0.0, -30.0, std::nan(""), std::numeric_limits<double>::infinity(), 1e-9, 1e12}) {
    EXPECT_THROW(exact_frame_rate(fps), Error) << fps;
  }
}

}  // namespace
}  // namespace wheelpose::motion
