#pragma once
// Zero-phase low-pass filtering of joint positions: a digital Butterworth filter designed like
// scipy.signal.butter (analog prototype, pre-warped bilinear transform) and applied forward and
// backward like scipy.signal.filtfilt (odd extension of 3 * (order + 1) samples at each end,
// steady-state initial conditions). The paper filters joint positions at 5 Hz, order 3.

#include <vector>

#include "motion/clip.h"

namespace wheelpose::motion {

struct FilterCoefficients {
  std::vector<double> b;  // numerator, length order + 1
  std::vector<double> a;  // denominator, a[0] == 1
};

// Low-pass Butterworth of `order` with cutoff `cutoff_hz` at sample rate `sample_rate_hz`.
// Requires 0 < cutoff < sample_rate / 2.
FilterCoefficients butterworth_lowpass(int order, double cutoff_hz, double sample_rate_hz);

// Samples each end is extended by (scipy's default padlen); a signal must be longer than this.
int filtfilt_padding(const FilterCoefficients& filter);

// Forward-backward filtering of one signal; signal.size() must exceed filtfilt_padding().
std::vector<double> filtfilt(const FilterCoefficients& filter, const std::vector<double>& signal);

// |H(e^{jw})| of the one-way filter at frequency `hz` (filtfilt's gain is its square).
double magnitude_response(const FilterCoefficients& filter, double hz, double sample_rate_hz);

// Filters every coordinate of every joint over time.
void lowpass_positions(std::vector<Pose>& frames, const FilterCoefficients& filter);

}  // namespace wheelpose::motion
