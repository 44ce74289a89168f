#include "motion/filter.h"

#include <Eigen/Dense>
#include <cmath>
#include <complex>
#include <numbers>

#include "core/error.h"

namespace wheelpose::motion {

namespace {

using Complex = std::complex<double>;

// Coefficients of prod(x - root) in descending powers (numpy.poly), real parts.
std::vector<double> polynomial_from_roots(const std::vector<Complex>& roots) {
  std::vector<Complex> coefficients = {1.0};
  for (const Complex& root : roots) {
    std::vector<Complex> next(coefficients.size() + 1, 0.0);
    for (std::size_t i = 0; i < coefficients.size(); ++i) {
      next[i] += coefficients[i];
      next[i + 1] -= coefficients[i] * root;
    }
    coefficients = std::move(next);
  }
  std::vector<double> real(coefficients.size());
  for (std::size_t i = 0; i < coefficients.size(); ++i) real[i] = coefficients[i].real();
  return real;
}

// Transposed direct form II, like scipy.signal.lfilter with initial state `state`.
std::vector<double> lfilter(const FilterCoefficients& f, const std::vector<double>& x,
                            std::vector<double> state) {
  const std::size_t n = f.b.size();
  std::vector<double> y(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double out = f.b[0] * x[i] + state[0];
    for (std::size_t k = 1; k < n; ++k) {
      const double carry = k < n - 1 ? state[k] : 0.0;
      state[k - 1] = f.b[k] * x[i] + carry - f.a[k] * out;
    }
    y[i] = out;
  }
  return y;
}

// Steady-state of the filter for a unit step input (scipy.signal.lfilter_zi).
std::vector<double> lfilter_zi(const FilterCoefficients& f) {
  const int n = static_cast<int>(f.a.size()) - 1;
  Eigen::MatrixXd i_minus_a = Eigen::MatrixXd::Identity(n, n);
  for (int col = 0; col < n; ++col) i_minus_a(col, 0) += f.a[col + 1];  // companion(a).T
  for (int row = 0; row + 1 < n; ++row) i_minus_a(row, row + 1) -= 1.0;
  Eigen::VectorXd rhs(n);
  for (int k = 0; k < n; ++k) rhs[k] = f.b[k + 1] - f.a[k + 1] * f.b[0];
  Eigen::VectorXd zi = i_minus_a.colPivHouseholderQr().solve(rhs);
  return std::vector<double>(zi.data(), zi.data() + n);
}

}  // namespace

FilterCoefficients butterworth_lowpass(int order, double cutoff_hz, double sample_rate_hz) {
  WHEELPOSE_CHECK(order >= 1);
  WHEELPOSE_CHECK(cutoff_hz > 0 && cutoff_hz < sample_rate_hz / 2);
  // Analog prototype poles on the left half of the unit circle, scaled to the pre-warped cutoff.
  const double nyquist_fraction = cutoff_hz / (sample_rate_hz / 2);
  const double sample_rate = 2.0;  // scipy designs in normalised frequency with fs = 2
  const double warped = 2 * sample_rate * std::tan(std::numbers::pi * nyquist_fraction / sample_rate);
  std::vector<Complex> poles;
  for (int k = -order + 1; k < order; k += 2) {
    poles.push_back(-std::exp(Complex(0, std::numbers::pi * k / (2.0 * order))) * warped);
  }
  double gain = std::pow(warped, order);
  // Bilinear transform: every analog zero at infinity becomes a digital zero at -1.
  const double fs2 = 2 * sample_rate;
  Complex denominator = 1.0;
  std::vector<Complex> digital_poles;
  for (const Complex& p : poles) {
    digital_poles.push_back((fs2 + p) / (fs2 - p));
    denominator *= fs2 - p;
  }
  gain *= (1.0 / denominator).real();
  FilterCoefficients f;
  f.b = polynomial_from_roots(std::vector<Complex>(order, Complex(-1.0, 0.0)));
  for (double& c : f.b) c *= gain;
  f.a = polynomial_from_roots(digital_poles);
  return f;
}

int filtfilt_padding(const FilterCoefficients& filter) {
  return 3 * static_cast<int>(std::max(filter.a.size(), filter.b.size()));
}

std::vector<double> filtfilt(const FilterCoefficients& filter, const std::vector<double>& signal) {
  const int pad = filtfilt_padding(filter);
  const int n = static_cast<int>(signal.size());
  WHEELPOSE_CHECK(n > pad);
  // Odd extension: reflect the signal about its end values.
  std::vector<double> extended;
  extended.reserve(n + 2 * pad);
  for (int i = pad; i >= 1; --i) extended.push_back(2 * signal[0] - signal[i]);
  extended.insert(extended.end(), signal.begin(), signal.end());
  for (int i = n - 2; i >= n - 1 - pad; --i) extended.push_back(2 * signal[n - 1] - signal[i]);

  const std::vector<double> zi = lfilter_zi(filter);
  auto scaled = [&](double x0) {
    std::vector<double> state(zi);
    for (double& s : state) s *= x0;
    return state;
  };
  std::vector<double> forward = lfilter(filter, extended, scaled(extended.front()));
  std::vector<double> reversed(forward.rbegin(), forward.rend());
  std::vector<double> backward = lfilter(filter, reversed, scaled(reversed.front()));
  return std::vector<double>(backward.rbegin() + pad, backward.rend() - pad);
}

double magnitude_response(const FilterCoefficients& filter, double hz, double sample_rate_hz) {
  const Complex z_inv = std::exp(Complex(0, -2 * std::numbers::pi * hz / sample_rate_hz));
  Complex num = 0, den = 0, power = 1;
  for (std::size_t k = 0; k < filter.b.size(); ++k) {
    num += filter.b[k] * power;
    den += filter.a[k] * power;
    power *= z_inv;
  }
  return std::abs(num / den);
}

void lowpass_positions(std::vector<Pose>& frames, const FilterCoefficients& filter) {
  std::vector<double> track(frames.size());
  for (int joint = 0; joint < kJointCount; ++joint) {
    for (int axis = 0; axis < 3; ++axis) {
      for (std::size_t f = 0; f < frames.size(); ++f) track[f] = frames[f][joint][axis];
      const std::vector<double> smooth = filtfilt(filter, track);
      for (std::size_t f = 0; f < frames.size(); ++f) frames[f][joint][axis] = smooth[f];
    }
  }
}

}  // namespace wheelpose::motion
