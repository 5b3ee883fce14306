// A known resonance after a switch, the tests' closed-form truth for the output dynamics after the operator
// (test_output_dynamics.cpp, test_output_dynamics_noise.cpp).
#pragma once

#include <cmath>
#include <numbers>
#include <vector>

#include "lashid/operator_fit/output_dynamics.hpp"

namespace lashid::test {

constexpr double kRate = 1024.0;
constexpr double kPi = std::numbers::pi;

// A(q) = 1 - 2 r cos(theta) q^-1 + r^2 q^-2 of the continuous pair s = -zeta w +- i w sqrt(1 - zeta^2) sampled at
// kRate (z = exp(s / kRate)), and b_0 = A(1), b_1 = b_2 = 0: static gain 1, the force reaches the sensor at once.
inline lashid::sim::OutputFilter resonance(double natural_hz, double zeta) {
  const double w = 2 * kPi * natural_hz;
  const double r = std::exp(-zeta * w / kRate);
  const double theta = w * std::sqrt(1 - zeta * zeta) / kRate;
  const double a1 = -2 * r * std::cos(theta), a2 = r * r;
  return {{a1, a2}, {1 + a1 + a2, 0, 0}};
}

// The switch with constant borders +-1 on v = amplitude(t) sin(2 pi f t): +1 while v rises, -1 while it falls,
// i.e. the sign of cos(2 pi f t) (the amplitude ramps slowly, so it does not move the reversals noticeably).
inline std::vector<double> switch_output(double hz, double seconds) {
  std::vector<double> w;
  for (int t = 0; t < static_cast<int>(seconds * kRate); ++t) {
    w.push_back(std::cos(2 * kPi * hz * t / kRate) >= 0 ? 1 : -1);
  }
  return w;
}

// y(t) = -a1 y(t-1) - a2 y(t-2) + b0 w(t), from rest at y0 = b0 w(0) / A(1) = w(0): written out here, not
// OutputFilter::apply, so the test does not check the filter against itself.
inline std::vector<double> through_resonance(const std::vector<double>& w, double natural_hz, double zeta) {
  const lashid::sim::OutputFilter f = resonance(natural_hz, zeta);
  std::vector<double> y(w.size());
  double y1 = w[0], y2 = w[0];
  for (std::size_t t = 0; t < w.size(); ++t) {
    y[t] = t == 0 ? w[0] : -f.a[0] * y1 - f.a[1] * y2 + f.b[0] * w[t];
    y2 = y1;
    y1 = y[t];
  }
  return y;
}

}  // namespace lashid::test
