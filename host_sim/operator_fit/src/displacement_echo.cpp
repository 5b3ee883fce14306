// The cross-spectrum of displacement and model error near one frequency (see displacement_echo.hpp).
#include "lashid/operator_fit/displacement_echo.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "fourier.hpp"

namespace lashid::sim {

namespace {

/// A coherence at least this large says that one signal linearly explains most of the other near that frequency
/// (the usual rule of thumb; fixed before any damper file was looked at this way).
constexpr double kCoherent = 0.5;
/// A gain this many times the slider's own stiffness is not the slider: it is a stiffer path (the rig).
constexpr double kStifferThanSlider = 3.0;

// A window of x, its mean removed, Hann weighted, into `out`.
void weighted_window(std::span<const double> x, const std::vector<double>& hann, std::vector<double>& out) {
  double mean = 0;
  for (double s : x) mean += s;
  mean /= static_cast<double>(x.size());
  out.resize(x.size());
  for (std::size_t k = 0; k < x.size(); ++k) out[k] = hann[k] * (x[k] - mean);
}

}  // namespace

DisplacementEcho displacement_echo(std::span<const double> v, std::span<const double> measured,
                                   std::span<const double> simulated, double sample_rate, double hz, double band_hz,
                                   double window_s) {
  const auto positive = [](double x) { return std::isfinite(x) && x > 0; };
  if (v.size() != measured.size() || v.size() != simulated.size() || !positive(sample_rate) || !positive(hz) ||
      !positive(window_s) || !(band_hz >= 0) || !std::isfinite(band_hz)) {
    throw std::invalid_argument(fmt::format(
        "displacement_echo: need equal sizes ({}, {}, {}), rate, hz and window positive ({}, {}, {}), band >= 0 ({})",
        v.size(), measured.size(), simulated.size(), sample_rate, hz, window_s, band_hz));
  }
  const double samples = std::round(window_s * sample_rate);
  const std::size_t length = samples >= 2 && samples <= static_cast<double>(v.size()) ? static_cast<std::size_t>(samples) : 0;
  DisplacementEcho out;
  out.hz = hz;
  if (length == 0 || v.size() < length + length / 2) return out;  // fewer than two windows: nothing to tell
  std::vector<double> error(v.size()), hann(length);
  for (std::size_t t = 0; t < v.size(); ++t) error[t] = measured[t] - simulated[t];
  for (std::size_t k = 0; k < length; ++k) {
    hann[k] = 0.5 * (1 - std::cos(2 * std::numbers::pi * static_cast<double>(k) / static_cast<double>(length - 1)));
  }
  // Each window is weighted once; its coefficients at every frequency of the band accumulate the spectra (Welch).
  struct Spectra {
    double hz;
    std::complex<double> cross{};  // sum of conj(V) E
    double vv = 0, ee = 0;         // sums of |V|^2 and |E|^2
  };
  std::vector<Spectra> band;
  for (double f = std::max(hz - band_hz, 1e-9); f <= hz + band_hz + 1e-9; f += 1.0) band.push_back({f});
  std::vector<double> wv, we;
  for (std::size_t start = 0; start + length <= v.size(); start += length / 2, ++out.windows) {
    weighted_window(v.subspan(start, length), hann, wv);
    weighted_window(std::span<const double>(error).subspan(start, length), hann, we);
    for (Spectra& s : band) {
      const std::complex<double> a = detail::fourier_coefficient(wv, s.hz, sample_rate);
      const std::complex<double> b = detail::fourier_coefficient(we, s.hz, sample_rate);
      s.cross += std::conj(a) * b;
      s.vv += std::norm(a);
      s.ee += std::norm(b);
    }
  }
  double weighted = 0, power = 0;
  for (const Spectra& s : band) {
    if (s.vv > 0 && s.ee > 0) {
      weighted += std::norm(s.cross) / (s.vv * s.ee) * s.ee;
      power += s.ee;
    }
    if (std::abs(s.hz - hz) < 0.5 && s.vv > 0) {
      const std::complex<double> transfer = s.cross / s.vv;
      out.gain = std::abs(transfer);
      out.phase_deg = std::arg(transfer) * 180 / std::numbers::pi;
    }
  }
  out.coherence = power > 0 ? weighted / power : 0.0;
  return out;
}

std::string displacement_echo_words(const DisplacementEcho& echo, double stiffness) {
  if (echo.windows < 2) {
    return fmt::format("not compared with the displacement: the record holds fewer than two windows ({})",
                       echo.windows);
  }
  const std::string numbers = fmt::format("coherence {:.2f} at {:.0f} Hz, {:.0f} per unit of v, phase {:+.0f} degrees",
                                          echo.coherence, echo.hz, echo.gain, echo.phase_deg);
  if (echo.coherence < kCoherent) {
    return fmt::format("not coherent with the displacement ({}): the oscillation keeps its own phase, which no "
                       "model of v predicts",
                       numbers);
  }
  if (std::abs(echo.phase_deg) <= 90) {
    return fmt::format("driven by the displacement ({}): a linear path from v beside the operator would follow it",
                       numbers);
  }
  if (std::isfinite(stiffness) && stiffness > 0 && echo.gain > kStifferThanSlider * stiffness) {
    return fmt::format("echoed by the displacement ({}, {:.0f} times the slider's stiffness of {:.1f}): the "
                       "displacement yields to the force (the compliance of the actuator and the rig) instead of "
                       "driving it, so the oscillation starts in the force path (chatter of the friction element or "
                       "a resonance of the rig); a filter of v could copy it only by reading the rig's reaction to "
                       "the force, which an imposed motion does not contain",
                       numbers, echo.gain / stiffness, stiffness);
  }
  return fmt::format("coherent with the displacement in antiphase ({}), at a gain within {:g} times the slider's "
                     "stiffness of {:.1f}: the displacement carries the oscillation in a way this analysis does not "
                     "name",
                     numbers, kStifferThanSlider, stiffness);
}

}  // namespace lashid::sim
