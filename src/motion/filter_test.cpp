#include "motion/filter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace wheelpose::motion {
namespace {

TEST(Butterworth, MatchesScipyAtTheAuthorsSettings) {
  // scipy.signal.butter(3, 5 / (0.5 * 20)) = b [1/6, 1/2, 1/2, 1/6], a [1, 0, 1/3, 0].
  auto f = butterworth_lowpass(3, 5.0, 20.0);
  ASSERT_EQ(f.b.size(), 4u);
  ASSERT_EQ(f.a.size(), 4u);
  const double b[] = {1.0 / 6, 0.5, 0.5, 1.0 / 6};
  const double a[] = {1.0, 0.0, 1.0 / 3, 0.0};
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(f.b[i], b[i], 1e-12);
    EXPECT_NEAR(f.a[i], a[i], 1e-12);
  }
  EXPECT_EQ(filtfilt_padding(f), 12);
}

TEST(Butterworth, MatchesBilinearTransformOfThePrototypeAt30Fps) {
  // Derived independently by substituting s = 2 fs (1 - z^-1) / (1 + z^-1) / wc into
  // 1 / (s^3 + 2 s^2 + 2 s + 1) with wc = 2 fs tan(pi fc / fs).
  auto f = butterworth_lowpass(3, 5.0, 30.0);
  const double b[] = {0.06385592453247639, 0.1915677735974292, 0.1915677735974292,
                      0.06385592453247639};
  const double a[] = {1.0, -0.9657797131791607, 0.5826441659843021, -0.10601705654533038};
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(f.b[i], b[i], 1e-12);
    EXPECT_NEAR(f.a[i], a[i], 1e-12);
  }
}

TEST(Butterworth, AnalyticMagnitudeResponse) {
  // A Butterworth low-pass has |H| = 1/sqrt(2) at the cutoff, 1 at DC, 0 at Nyquist.
  for (double fps : {20.0, 30.0, 60.0, 120.0}) {
    auto f = butterworth_lowpass(3, 5.0, fps);
    EXPECT_NEAR(magnitude_response(f, 0.0, fps), 1.0, 1e-12);
    EXPECT_NEAR(magnitude_response(f, 5.0, fps), 1.0 / std::sqrt(2.0), 1e-9);
    EXPECT_NEAR(magnitude_response(f, fps / 2, fps), 0.0, 1e-9);
  }
}

TEST(Filtfilt, MeasuredResponseEqualsSquaredAnalyticResponse) {
  // Filter long sinusoids and compare the steady-state amplitude in the middle with |H|^2.
  const double fps = 60.0;
  auto f = butterworth_lowpass(3, 5.0, fps);
  for (double hz : {0.5, 2.0, 4.0, 5.0, 6.0, 8.0, 12.0}) {
    std::vector<double> x(3600);
    for (std::size_t i = 0; i < x.size(); ++i) x[i] = std::sin(2 * std::numbers::pi * hz * i / fps);
    auto y = filtfilt(f, x);
    // RMS over a whole number of periods (20 s) gives the amplitude without sampling the peak.
    double sum_sq = 0;
    for (std::size_t i = 1200; i < 2400; ++i) sum_sq += y[i] * y[i];
    const double amplitude = std::sqrt(2 * sum_sq / 1200);
    const double expected = std::pow(magnitude_response(f, hz, fps), 2);
    EXPECT_NEAR(amplitude, expected, 1e-3) << hz << " Hz";
  }
}

TEST(Filtfilt, KeepsConstantsExactlyAndLinesAwayFromTheEndsAndIsZeroPhase) {
  auto f = butterworth_lowpass(3, 5.0, 20.0);
  std::vector<double> constant(20, 1.25);
  for (double v : filtfilt(f, constant)) EXPECT_NEAR(v, 1.25, 1e-12);
  std::vector<double> line(60);
  for (std::size_t i = 0; i < line.size(); ++i) line[i] = 0.3 * i - 2.0;
  auto y = filtfilt(f, line);
  for (std::size_t i = 15; i + 15 < line.size(); ++i) EXPECT_NEAR(y[i], line[i], 1e-6);
  // Zero phase: a symmetric pulse stays symmetric about its centre.
  std::vector<double> pulse(41, 0.0);
  pulse[20] = 1.0;
  auto p = filtfilt(f, pulse);
  for (int k = 1; k < 15; ++k) EXPECT_NEAR(p[20 - k], p[20 + k], 1e-12);
}

TEST(Filtfilt, GoldenImpulseResponse) {
  // Away from the ends the zero-phase impulse response is the autocorrelation of the one-way
  // response of b = [1/6, 1/2, 1/2, 1/6], a = [1, 0, 1/3, 0]: 1/2, 11/36, 0, -2/27.
  auto f = butterworth_lowpass(3, 5.0, 20.0);
  std::vector<double> x(31, 0.0);
  x[15] = 1.0;
  auto y = filtfilt(f, x);
  const double expected[] = {-2.0 / 27, 0.0, 11.0 / 36, 0.5, 11.0 / 36, 0.0, -2.0 / 27};
  for (int k = 0; k < 7; ++k) EXPECT_NEAR(y[12 + k], expected[k], 1e-9) << k;
}

TEST(Filtfilt, GoldenValuesNearTheEndsPinTheOddPadding) {
  // A reference run of scipy's algorithm (odd padding 12, lfilter_zi = [5/6, 1/3, 1/6]).
  std::vector<double> x(20);
  for (int i = 0; i < 20; ++i) x[i] = (i % 5) * 0.1 + (i == 3 ? 0.3 : 0.0);
  auto y = filtfilt(butterworth_lowpass(3, 5.0, 20.0), x);
  const double expected[] = {4.936163407160549e-05, 0.08630971026923384, 0.3079185207981357,
                             0.481895438617691,     0.37355556903880954, 0.11570549433846294};
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(y[i], expected[i], 1e-12) << i;
}

}  // namespace
}  // namespace wheelpose::motion
