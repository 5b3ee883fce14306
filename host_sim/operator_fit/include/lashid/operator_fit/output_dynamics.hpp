// Linear dynamics after a hysteresis operator (the paper's block structure: operator -> B(q)/A(q)), identified from
// measured records: the operator's simulated output w = F[v] is the filter's input, the measured force its output
// (docs/friction-damper.md, "Dynamics after the friction element").
#pragma once

#include <complex>
#include <span>
#include <vector>

namespace lashid::sim {

/// y(t) = B(q)/A(q) w(t) with A(q) = 1 + a_1 q^-1 + ... + a_n q^-n and B(q) = b_0 + b_1 q^-1 + ... + b_n q^-n.
/// b_0 is kept: the friction element's force reaches the load cell within the sample, only its ringing is delayed.
struct OutputFilter {
  std::vector<double> a;  ///< a_1..a_n
  std::vector<double> b;  ///< b_0..b_n (n + 1 values)

  int order() const { return static_cast<int>(a.size()); }
  /// B(1) / A(1): the filter's static gain (1 when the operator alone gives the right static force).
  double dc_gain() const;
  /// The filter run on w from rest: before t = 0 every input equals w[0] and every output equals y0 (the record's
  /// first measured output, so the start does not depend on the coefficients). The first output is y0.
  std::vector<double> apply(std::span<const double> w, double y0) const;
};

/// A root of z^n + a_1 z^(n-1) + ... + a_n and its continuous-time meaning at the given sampling rate:
/// s = ln(z) * rate, natural frequency |s| / 2 pi, damped (ringing) frequency |Im s| / 2 pi, zeta = -Re s / |s|.
struct FilterPole {
  std::complex<double> z;
  double natural_hz = 0;
  double damped_hz = 0;
  double zeta = 0;
};
/// The poles of `filter`, sorted by decreasing |z| (slowest decay first). Throws std::invalid_argument for a rate
/// that is not positive and finite.
std::vector<FilterPole> filter_poles(const OutputFilter& filter, double sample_rate);
/// The pole that rings longest: the oscillating pole (Im z > 0) of largest |z|; without one, the pole of largest
/// |z|. Returns false when the filter has no poles.
bool dominant_pole(const std::vector<FilterPole>& poles, FilterPole* out);

/// One training file for the filter: the operator's simulated output w and the measured output y, same length.
struct FilterData {
  std::vector<double> w;
  std::vector<double> y;
};

/// Equation-error least squares (ARX) of order n over all files: y(t) + sum a_k y(t-k) = sum b_k w(t-k), for
/// t >= n in each file. Biased when y is noisy (the regressors hold past y); a starting point for
/// refine_output_error(). Throws std::invalid_argument for order < 1, no file, files of unequal w/y length, or
/// fewer samples than parameters.
OutputFilter fit_arx(const std::vector<FilterData>& files, int order);
/// Output-error refinement: Levenberg-Marquardt on the squared simulated error sum (y - apply(w, y[0]))^2 over
/// all files, from `start`; steps that make A unstable (a pole with |z| >= 1) or do not lower the error are
/// refused. An unstable `start` is first pulled inside the unit circle (its poles scaled to |z| <= 0.999).
OutputFilter refine_output_error(const std::vector<FilterData>& files, OutputFilter start, int iterations = 40);

struct OutputDynamicsOptions {
  int min_order = 2;
  int max_order = 4;
  /// An order is taken over a lower one only if it raises the cross-validated fit by more than this (points).
  double order_tolerance = 0.5;
  int iterations = 40;  ///< output-error iterations per fit
};

struct OrderScore {
  int order = 0;
  double cv_fit = 0;  ///< mean fit (%) on each training file held out from the fit (leave one file out)
};

struct OutputDynamicsFit {
  OutputFilter filter;              ///< of the chosen order, refitted on all training files
  std::vector<OrderScore> scores;   ///< one per candidate order
  double fit_train = 0;             ///< mean fit (%) of the chosen filter on the training files
};

/// Chooses the order by leaving one training file out at a time (fit on the others, score on it; with a single
/// file, its first and second halves), then refits that order on all files: ARX, then output error. Training
/// data only. Throws std::invalid_argument for an empty list or min_order < 1 or max_order < min_order.
OutputDynamicsFit fit_output_dynamics(const std::vector<FilterData>& train, const OutputDynamicsOptions& options = {});

/// How much of a model's error u - u_sim oscillates: the error minus its centred moving mean over `window_s`
/// seconds (what changes faster than about 1 / window_s Hz), its share of the error's energy, and the frequency
/// (1 Hz steps from `from_hz` to `to_hz`) where the amplitude of that fast part's Fourier transform peaks.
struct ErrorOscillation {
  double fast_share = 0;  ///< sum of squares of the fast part / sum of squares of the error (0 for no error)
  double peak_hz = 0;
  double peak_amplitude = 0;  ///< amplitude of a sinusoid at peak_hz with the same Fourier coefficient
};
/// Throws std::invalid_argument for unequal sizes, a rate or window that is not positive, or from_hz > to_hz.
ErrorOscillation error_oscillation(std::span<const double> measured, std::span<const double> simulated,
                                   double sample_rate, double window_s = 0.1, double from_hz = 5,
                                   double to_hz = 100);

}  // namespace lashid::sim
