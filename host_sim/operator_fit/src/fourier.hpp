// Private to operator_fit: one Fourier coefficient of a record (error_oscillation, displacement_echo).
#pragma once

#include <complex>
#include <numbers>
#include <span>

namespace lashid::sim::detail {

/// sum_t x[t] exp(-i 2 pi hz t / rate), by a rotating phasor: one complex multiplication per sample, no table.
inline std::complex<double> fourier_coefficient(std::span<const double> x, double hz, double rate) {
  const std::complex<double> turn = std::polar(1.0, -2 * std::numbers::pi * hz / rate);
  std::complex<double> phasor = 1.0, sum = 0.0;
  for (double sample : x) {
    sum += sample * phasor;
    phasor *= turn;
  }
  return sum;
}

}  // namespace lashid::sim::detail
