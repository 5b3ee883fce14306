// Linear dynamics after the operator: filtering, poles, ARX, output-error refinement, order choice (see
// output_dynamics.hpp).
#include "lashid/operator_fit/output_dynamics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include <Eigen/Dense>
#include <fmt/format.h>

#include "lashid/stats/metrics.hpp"
#include "lashid/stats/polynomial.hpp"
#include "fourier.hpp"

namespace lashid::sim {

namespace {

using stats::is_stable;
using stats::polynomial_from_roots;
using stats::polynomial_roots;

void require_files(const std::vector<FilterData>& files) {
  if (files.empty()) throw std::invalid_argument("output dynamics: no training files");
  for (const auto& f : files) {
    if (f.w.size() != f.y.size()) {
      throw std::invalid_argument(fmt::format("output dynamics: operator output has {} samples, measurement {}",
                                              f.w.size(), f.y.size()));
    }
    if (f.w.empty()) throw std::invalid_argument("output dynamics: an empty file");
  }
}

// Parameters as one vector: a_1..a_n, then b_0..b_n.
Eigen::VectorXd to_vector(const OutputFilter& f) {
  Eigen::VectorXd theta(static_cast<Eigen::Index>(f.a.size() + f.b.size()));
  Eigen::Index i = 0;
  for (const double x : f.a) theta(i++) = x;
  for (const double x : f.b) theta(i++) = x;
  return theta;
}

OutputFilter from_vector(const Eigen::VectorXd& theta, int order) {
  OutputFilter f;
  for (int k = 0; k < order; ++k) f.a.push_back(theta(k));
  for (int k = 0; k <= order; ++k) f.b.push_back(theta(order + k));
  return f;
}

// Simulated error r = y - apply(w, y0) of every file stacked, and (if jacobian) d(y_sim)/d(theta) row by row: the
// sensitivities obey the same recursion as the output (d/da_i: -y_sim(t-i); d/db_j: w(t-j) as the input).
double simulated_error(const std::vector<FilterData>& files, const OutputFilter& f, Eigen::VectorXd* residual,
                       Eigen::MatrixXd* jacobian) {
  const int n = f.order();
  const Eigen::Index p = 2 * n + 1;
  std::size_t total = 0;
  for (const auto& d : files) total += d.y.size();
  if (residual) residual->resize(static_cast<Eigen::Index>(total));
  if (jacobian) jacobian->setZero(static_cast<Eigen::Index>(total), p);
  double sse = 0;
  Eigen::Index row = 0;
  for (const auto& d : files) {
    const std::vector<double> y_sim = f.apply(d.w, d.y.front());
    const auto lags = static_cast<std::size_t>(n);
    for (std::size_t t = 0; t < d.y.size(); ++t, ++row) {
      const double r = d.y[t] - y_sim[t];
      sse += r * r;
      if (residual) (*residual)(row) = r;
      if (!jacobian || t == 0) continue;  // the first output is the measured y0, whatever theta
      auto& J = *jacobian;
      for (std::size_t k = 1; k <= lags; ++k) {
        J(row, static_cast<Eigen::Index>(k - 1)) = -(t >= k ? y_sim[t - k] : d.y.front());
      }
      for (std::size_t j = 0; j <= lags; ++j) {
        J(row, static_cast<Eigen::Index>(lags + j)) = t >= j ? d.w[t - j] : d.w[0];
      }
      // Rows before the file's first sample do not exist; the row of t = 0 is zero.
      for (std::size_t k = 1; k <= lags && k <= t; ++k) {
        J.row(row) -= f.a[k - 1] * J.row(row - static_cast<Eigen::Index>(k));
      }
    }
  }
  return sse;
}

double mean_fit(const std::vector<FilterData>& files, const OutputFilter& f) {
  double sum = 0;
  for (const auto& d : files) {
    const std::vector<double> y_sim = f.apply(d.w, d.y.front());
    const bool finite = std::all_of(y_sim.begin(), y_sim.end(), [](double x) { return std::isfinite(x); });
    sum += finite ? stats::fit_percent(d.y, y_sim) : -std::numeric_limits<double>::infinity();
  }
  return sum / static_cast<double>(files.size());
}

// A lightly damped resonance of unit static gain, A(q) = 1 - 2 r cos(theta) q^-1 + r^2 q^-2 and b_0 = A(1), made
// of order n by a fast pole at 0.2 cancelled by a zero at 0.2 (the refinement moves them where the data want).
OutputFilter resonance_start(double natural_hz, double zeta, double rate, int order) {
  const double w = 2 * std::numbers::pi * natural_hz / rate;
  const double r = std::exp(-zeta * w);
  const double theta = w * std::sqrt(std::max(0.0, 1 - zeta * zeta));
  std::vector<std::complex<double>> poles{std::polar(r, theta), std::polar(r, -theta)};
  std::vector<std::complex<double>> zeros;
  while (static_cast<int>(poles.size()) < order) {
    poles.emplace_back(0.2);
    zeros.emplace_back(0.2);
  }
  while (static_cast<int>(poles.size()) > order) poles.pop_back();  // order 1: one real pole at r
  if (order == 1) poles.front() = r;
  OutputFilter f;
  f.a = polynomial_from_roots(poles);
  const std::vector<double> monic_b = polynomial_from_roots(zeros);
  f.b.assign(static_cast<std::size_t>(order) + 1, 0.0);
  f.b[0] = 1.0;
  for (std::size_t k = 0; k < monic_b.size(); ++k) f.b[k + 1] = monic_b[k];
  const double gain = f.dc_gain();
  for (double& x : f.b) x /= gain;
  return f;
}

// At a high sampling rate the equation error (ARX) is badly biased by sensor noise, and the output-error cost has
// local minima, so the refinement starts twice: from ARX and from the best of a grid of resonances (0.5 to 200 Hz
// at the rate 1024, damping 0.05 to 0.7, in units of the sampling rate); the lower simulated error wins.
OutputFilter fit_order(const std::vector<FilterData>& files, int order, int iterations) {
  constexpr double kReferenceRate = 1024.0;  // the grid in Hz at 1024 Hz; only its ratio to the rate matters
  OutputFilter grid_best;
  double grid_sse = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 24; ++i) {
    const double hz = 0.5 * std::pow(400.0, i / 23.0);
    for (const double zeta : {0.05, 0.1, 0.2, 0.4, 0.7}) {
      const OutputFilter candidate = resonance_start(hz, zeta, kReferenceRate, order);
      const double sse = simulated_error(files, candidate, nullptr, nullptr);
      if (sse < grid_sse) {
        grid_sse = sse;
        grid_best = candidate;
      }
    }
  }
  const OutputFilter from_grid = refine_output_error(files, grid_best, iterations);
  const OutputFilter from_arx = refine_output_error(files, fit_arx(files, order), iterations);
  return simulated_error(files, from_grid, nullptr, nullptr) <= simulated_error(files, from_arx, nullptr, nullptr)
             ? from_grid
             : from_arx;
}

}  // namespace

double OutputFilter::dc_gain() const {
  double num = 0, den = 1;
  for (const double x : b) num += x;
  for (const double x : a) den += x;
  return num / den;
}

std::vector<double> OutputFilter::apply(std::span<const double> w, double y0) const {
  std::vector<double> y(w.size());
  if (w.empty()) return y;
  y[0] = y0;
  const std::size_t n = a.size();
  for (std::size_t t = 1; t < w.size(); ++t) {
    double acc = 0;
    for (std::size_t k = 1; k <= n; ++k) acc -= a[k - 1] * (t >= k ? y[t - k] : y0);
    for (std::size_t j = 0; j < b.size(); ++j) acc += b[j] * (t >= j ? w[t - j] : w[0]);
    y[t] = acc;
  }
  return y;
}

std::vector<FilterPole> filter_poles(const OutputFilter& filter, double sample_rate) {
  if (!(sample_rate > 0) || !std::isfinite(sample_rate)) {
    throw std::invalid_argument(fmt::format("filter_poles: sampling rate must be positive, got {}", sample_rate));
  }
  std::vector<FilterPole> poles;
  for (const auto& z : polynomial_roots(filter.a)) {
    FilterPole p{z, 0, 0, 0};
    const std::complex<double> s = std::log(z) * sample_rate;  // a pole at z = 0 gives -inf: no dynamics
    if (std::isfinite(s.real())) {
      p.natural_hz = std::abs(s) / (2 * std::numbers::pi);
      p.damped_hz = std::fabs(s.imag()) / (2 * std::numbers::pi);
      p.zeta = std::abs(s) > 0 ? -s.real() / std::abs(s) : 0.0;
    }
    poles.push_back(p);
  }
  std::stable_sort(poles.begin(), poles.end(),
                   [](const FilterPole& x, const FilterPole& y) { return std::abs(x.z) > std::abs(y.z); });
  return poles;
}

bool dominant_pole(const std::vector<FilterPole>& poles, FilterPole* out) {
  if (poles.empty()) return false;
  const FilterPole* best = nullptr;
  for (const auto& p : poles) {
    if (p.z.imag() > 0 && (!best || std::abs(p.z) > std::abs(best->z))) best = &p;
  }
  *out = best ? *best : poles.front();  // poles are sorted by decreasing |z|
  return true;
}

OutputFilter fit_arx(const std::vector<FilterData>& files, int order) {
  if (order < 1) throw std::invalid_argument(fmt::format("output dynamics: order must be >= 1, got {}", order));
  require_files(files);
  const auto n = static_cast<std::size_t>(order);
  std::size_t rows = 0;
  for (const auto& d : files) rows += d.y.size() > n ? d.y.size() - n : 0;
  const auto p = static_cast<Eigen::Index>(2 * n + 1);
  if (rows < static_cast<std::size_t>(p)) {
    throw std::invalid_argument(fmt::format("output dynamics: {} equations for {} parameters", rows, p));
  }
  Eigen::MatrixXd phi(static_cast<Eigen::Index>(rows), p);
  Eigen::VectorXd target(static_cast<Eigen::Index>(rows));
  Eigen::Index row = 0;
  for (const auto& d : files) {
    for (std::size_t t = n; t < d.y.size(); ++t, ++row) {
      for (std::size_t k = 1; k <= n; ++k) phi(row, static_cast<Eigen::Index>(k - 1)) = -d.y[t - k];
      for (std::size_t j = 0; j <= n; ++j) phi(row, static_cast<Eigen::Index>(n + j)) = d.w[t - j];
      target(row) = d.y[t];
    }
  }
  // QR, not the normal equations: at 1024 Hz the lagged outputs are nearly collinear.
  const Eigen::VectorXd theta = phi.colPivHouseholderQr().solve(target);
  return from_vector(theta, order);
}

OutputFilter refine_output_error(const std::vector<FilterData>& files, OutputFilter start, int iterations) {
  require_files(files);
  const int n = start.order();
  if (n < 1 || start.b.size() != static_cast<std::size_t>(n) + 1) {
    throw std::invalid_argument("output dynamics: a filter of order n needs n a's and n + 1 b's");
  }
  if (!is_stable(start.a)) {
    std::vector<std::complex<double>> roots = polynomial_roots(start.a);
    for (auto& r : roots) {
      if (std::abs(r) > 0.999) r *= 0.999 / std::abs(r);
    }
    start.a = polynomial_from_roots(roots);
  }
  OutputFilter current = std::move(start);
  Eigen::VectorXd residual;
  Eigen::MatrixXd jacobian;
  double sse = simulated_error(files, current, &residual, &jacobian);
  double lambda = 1e-3;
  for (int it = 0; it < iterations; ++it) {
    // Scale the columns (a and b differ by orders of magnitude), then solve [J; sqrt(lambda) I] delta = [r; 0].
    const Eigen::VectorXd scale = jacobian.colwise().norm().transpose().cwiseMax(1e-300);
    const Eigen::MatrixXd scaled = jacobian * scale.cwiseInverse().asDiagonal();
    bool improved = false;
    while (lambda < 1e12) {
      const Eigen::Index p = scaled.cols();
      Eigen::MatrixXd augmented(scaled.rows() + p, p);
      augmented << scaled, std::sqrt(lambda) * Eigen::MatrixXd::Identity(p, p);
      Eigen::VectorXd rhs = Eigen::VectorXd::Zero(scaled.rows() + p);
      rhs.head(scaled.rows()) = residual;
      const Eigen::VectorXd step = augmented.colPivHouseholderQr().solve(rhs).cwiseQuotient(scale);
      const OutputFilter candidate = from_vector(to_vector(current) + step, n);
      if (is_stable(candidate.a)) {
        const double candidate_sse = simulated_error(files, candidate, nullptr, nullptr);
        if (candidate_sse < sse) {
          const bool converged = sse - candidate_sse < 1e-10 * sse;
          current = candidate;
          sse = simulated_error(files, current, &residual, &jacobian);
          lambda = std::max(lambda / 10, 1e-9);
          improved = !converged;
          break;
        }
      }
      lambda *= 10;
    }
    if (!improved) break;
  }
  return current;
}

OutputDynamicsFit fit_output_dynamics(const std::vector<FilterData>& train, const OutputDynamicsOptions& options) {
  require_files(train);
  if (options.min_order < 1 || options.max_order < options.min_order) {
    throw std::invalid_argument(fmt::format("output dynamics: orders {}..{} (need 1 <= min <= max)",
                                            options.min_order, options.max_order));
  }
  // Folds: each file held out once; a single file is split into halves instead.
  std::vector<std::pair<std::vector<FilterData>, std::vector<FilterData>>> folds;  // (fit on, score on)
  if (train.size() == 1) {
    const auto& d = train.front();
    const auto half = static_cast<std::ptrdiff_t>(d.y.size() / 2);
    const FilterData first{{d.w.begin(), d.w.begin() + half}, {d.y.begin(), d.y.begin() + half}};
    const FilterData second{{d.w.begin() + half, d.w.end()}, {d.y.begin() + half, d.y.end()}};
    folds.push_back({{first}, {second}});
    folds.push_back({{second}, {first}});
  } else {
    for (std::size_t held = 0; held < train.size(); ++held) {
      std::vector<FilterData> fit_on;
      for (std::size_t k = 0; k < train.size(); ++k) {
        if (k != held) fit_on.push_back(train[k]);
      }
      folds.push_back({std::move(fit_on), {train[held]}});
    }
  }
  OutputDynamicsFit out;
  int chosen = options.min_order;
  double chosen_score = -std::numeric_limits<double>::infinity();
  for (int order = options.min_order; order <= options.max_order; ++order) {
    double sum = 0;
    for (const auto& [fit_on, score_on] : folds) {
      sum += mean_fit(score_on, fit_order(fit_on, order, options.iterations));
    }
    const double score = sum / static_cast<double>(folds.size());
    out.scores.push_back({order, score});
    // A higher order must earn its parameters: it replaces the current choice only by more than the tolerance.
    if (score > chosen_score + (order == options.min_order ? 0.0 : options.order_tolerance)) {
      chosen = order;
      chosen_score = score;
    }
  }
  out.filter = fit_order(train, chosen, options.iterations);
  out.fit_train = mean_fit(train, out.filter);
  return out;
}

ErrorOscillation error_oscillation(std::span<const double> measured, std::span<const double> simulated,
                                   double sample_rate, double window_s, double from_hz, double to_hz) {
  if (measured.size() != simulated.size() || !(sample_rate > 0) || !(window_s > 0) || !(from_hz <= to_hz)) {
    throw std::invalid_argument(fmt::format(
        "error_oscillation: need equal sizes ({} vs {}), rate > 0 ({}), window > 0 ({}), from <= to ({}, {})",
        measured.size(), simulated.size(), sample_rate, window_s, from_hz, to_hz));
  }
  const std::size_t n = measured.size();
  std::vector<double> error(n), fast(n);
  for (std::size_t t = 0; t < n; ++t) error[t] = measured[t] - simulated[t];
  // Centred moving mean by a running sum; the window shrinks at the ends of the record.
  // Clamped to the record before the cast, so that a huge or infinite sample rate stays defined.
  const double half_window = std::round(window_s * sample_rate / 2);
  const auto half = static_cast<std::size_t>(
      half_window >= 1 ? std::min(half_window, static_cast<double>(std::max<std::size_t>(n, 1))) : 1.0);
  std::vector<double> cumulative(n + 1, 0.0);
  for (std::size_t t = 0; t < n; ++t) cumulative[t + 1] = cumulative[t] + error[t];
  double total = 0, fast_energy = 0;
  for (std::size_t t = 0; t < n; ++t) {
    const std::size_t lo = t >= half ? t - half : 0, hi = std::min(n, t + half + 1);
    fast[t] = error[t] - (cumulative[hi] - cumulative[lo]) / static_cast<double>(hi - lo);
    total += error[t] * error[t];
    fast_energy += fast[t] * fast[t];
  }
  ErrorOscillation out;
  out.fast_share = total > 0 ? fast_energy / total : 0.0;
  for (double hz = from_hz; hz <= to_hz + 1e-9; hz += 1.0) {
    const std::complex<double> sum = detail::fourier_coefficient(fast, hz, sample_rate);
    const double amplitude = n > 0 ? 2 * std::abs(sum) / static_cast<double>(n) : 0.0;
    if (amplitude > out.peak_amplitude) {
      out.peak_amplitude = amplitude;
      out.peak_hz = hz;
    }
  }
  return out;
}

}  // namespace lashid::sim
