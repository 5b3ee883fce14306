// Residual statistics: see statistics.hpp for the formulas and references.
#include "lashid/stats/statistics.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

namespace lashid::sim::stats {

namespace {

constexpr double epsilon = std::numeric_limits<double>::epsilon();
constexpr double infinity = std::numeric_limits<double>::infinity();
// Relative convergence threshold of the series and continued fractions, a few ulp.
constexpr double convergence = 4.0 * epsilon;
// Guard against a vanishing denominator in the modified Lentz method.
constexpr double lentz_tiny = 1e-300;
// Enough for a, b up to ~1e8 (both the series and the fractions need O(sqrt(max(a, b))) terms).
constexpr int max_iterations = 200000;

[[noreturn]] void fail(const std::string& function, const std::string& message) {
  throw std::invalid_argument("lashid::sim::stats::" + function + ": " + message);
}

void require_not_nan(const char* function, const char* name, double value) {
  if (std::isnan(value)) fail(function, fmt::format("{} is NaN", name));
}

void require_positive_finite(const char* function, const char* name, double value) {
  if (!std::isfinite(value) || value <= 0.0) fail(function, fmt::format("{} must be finite and > 0, got {}", name, value));
}

void require_finite_samples(const char* function, const char* name, std::span<const double> x) {
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (!std::isfinite(x[i])) fail(function, fmt::format("{}[{}] is not finite ({})", name, i, x[i]));
  }
}

void require_min_size(const char* function, const char* name, std::span<const double> x, std::size_t min_size) {
  if (x.size() < min_size) {
    fail(function, fmt::format("{} needs at least {} samples, got {}", name, min_size, x.size()));
  }
}

void require_not_constant(const char* function, const char* name, std::span<const double> x) {
  const auto [lowest, highest] = std::minmax_element(x.begin(), x.end());
  if (*lowest == *highest) fail(function, fmt::format("{} has zero variance (all {} samples equal {})", name, x.size(), *lowest));
}

// 0 <= lag < n.
void require_lag(const char* function, const char* name, int lag, int min_lag, std::size_t n) {
  if (lag < min_lag || static_cast<std::size_t>(lag) >= n) {
    fail(function, fmt::format("{} must be in [{}, N - 1] = [{}, {}], got {}", name, min_lag, min_lag, n - 1, lag));
  }
}

double mean(std::span<const double> x) {
  double sum = 0.0;
  for (const double v : x) sum += v;
  return sum / static_cast<double>(x.size());
}

std::vector<double> deviations(std::span<const double> x) {
  const double m = mean(x);
  std::vector<double> d(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) d[i] = x[i] - m;
  return d;
}

double sum_of_squares(const std::vector<double>& d) {
  double s = 0.0;
  for (const double v : d) s += v * v;
  return s;
}

// Modified Lentz evaluation of f = b0 + a1 / (b1 + a2 / (b2 + ...)), with (a_n, b_n) = term(n), n >= 1.
template <typename Term>
double continued_fraction(double b0, Term term, const char* function) {
  double f = b0 == 0.0 ? lentz_tiny : b0;
  double c = f;
  double d = 0.0;
  for (int n = 1; n <= max_iterations; ++n) {
    const auto [a_n, b_n] = term(n);
    d = b_n + a_n * d;
    if (std::fabs(d) < lentz_tiny) d = lentz_tiny;
    c = b_n + a_n / c;
    if (std::fabs(c) < lentz_tiny) c = lentz_tiny;
    d = 1.0 / d;
    const double delta = c * d;
    f *= delta;
    if (std::fabs(delta - 1.0) < convergence) return f;
  }
  throw std::runtime_error(fmt::format("lashid::sim::stats::{}: continued fraction did not converge", function));
}

// {P(a, x), Q(a, x)}, a > 0, x >= 0 finite.
std::pair<double, double> regularized_gamma(double a, double x) {
  if (x == 0.0) return {0.0, 1.0};
  const double log_prefactor = a * std::log(x) - x - std::lgamma(a);  // x^a e^-x / Gamma(a)
  if (x < a + 1.0) {
    // P = x^a e^-x / Gamma(a) * sum_{n>=0} x^n / (a (a+1) ... (a+n)).
    double term = 1.0 / a;
    double sum = term;
    for (int n = 1; n <= max_iterations; ++n) {
      term *= x / (a + static_cast<double>(n));
      sum += term;
      if (std::fabs(term) < std::fabs(sum) * convergence) {
        const double p = std::min(1.0, sum * std::exp(log_prefactor));
        return {p, 1.0 - p};
      }
    }
    throw std::runtime_error("lashid::sim::stats::regularized_gamma_q: series did not converge");
  }
  // Q = x^a e^-x / Gamma(a) / K, K = (x+1-a) - 1(1-a) / ((x+3-a) - 2(2-a) / ((x+5-a) - ...)).
  const double k = continued_fraction(
      x + 1.0 - a,
      [a, x](int n) {
        const double nd = static_cast<double>(n);
        return std::pair{-nd * (nd - a), x + 2.0 * nd + 1.0 - a};
      },
      "regularized_gamma_q");
  const double q = std::min(1.0, std::exp(log_prefactor) / k);
  return {1.0 - q, q};
}

// 1 + d1 / (1 + d2 / (1 + ...)) of A&S 26.5.8.
double beta_fraction(double a, double b, double x) {
  return continued_fraction(
      1.0,
      [a, b, x](int n) {
        const double m = static_cast<double>(n / 2);
        double d = 0.0;
        if (n % 2 == 1) {  // d_{2m+1}
          d = -(a + m) * (a + b + m) * x / ((a + 2.0 * m) * (a + 2.0 * m + 1.0));
        } else {  // d_{2m}
          d = m * (b - m) * x / ((a + 2.0 * m - 1.0) * (a + 2.0 * m));
        }
        return std::pair{d, 1.0};
      },
      "regularized_beta");
}

// {I_x(a, b), 1 - I_x(a, b)} with y = 1 - x supplied separately (exactly, by the caller) so that either tail
// is obtained without cancellation. a, b > 0; x, y in [0, 1].
std::pair<double, double> regularized_beta_pair(double a, double b, double x, double y) {
  if (x <= 0.0) return {0.0, 1.0};
  if (y <= 0.0) return {1.0, 0.0};
  const double log_beta = std::lgamma(a) + std::lgamma(b) - std::lgamma(a + b);
  const double prefactor = std::exp(a * std::log(x) + b * std::log(y) - log_beta);  // x^a y^b / B(a, b)
  if (x < (a + 1.0) / (a + b + 2.0)) {
    const double lower = std::min(1.0, prefactor / (a * beta_fraction(a, b, x)));
    return {lower, 1.0 - lower};
  }
  const double upper = std::min(1.0, prefactor / (b * beta_fraction(b, a, y)));  // I_y(b, a)
  return {1.0 - upper, upper};
}

double normal_density(double z) { return std::exp(-0.5 * z * z) * (0.5 * std::numbers::inv_sqrtpi * std::numbers::sqrt2); }

// Phi^{-1}(p) for 0 < p < 1/2 (negative result).
double lower_normal_quantile(double p) {
  // A&S 26.2.23 for the upper-tail probability p: |error| < 4.5e-4.
  const double t = std::sqrt(-2.0 * std::log(p));
  const double numerator = 2.515517 + t * (0.802853 + t * 0.010328);
  const double denominator = 1.0 + t * (1.432788 + t * (0.189269 + t * 0.001308));
  double z = -(t - numerator / denominator);
  // Halley's method on F(z) = Phi(z) - p: z <- z - u / (1 + z u / 2), u = F / F' (F'' / F' = -z).
  for (int i = 0; i < 8; ++i) {
    const double density = normal_density(z);
    if (density == 0.0) break;
    const double u = (normal_cdf(z) - p) / density;
    const double step = u / (1.0 + 0.5 * z * u);
    z -= step;
    if (std::fabs(step) <= epsilon * std::fabs(z)) break;
  }
  return z;
}

}  // namespace

double normal_cdf(double z) {
  require_not_nan("normal_cdf", "z", z);
  return 0.5 * std::erfc(-z * (0.5 * std::numbers::sqrt2));
}

double normal_quantile(double p) {
  if (!(p > 0.0 && p < 1.0)) fail("normal_quantile", fmt::format("p must be in (0, 1), got {}", p));
  if (p == 0.5) return 0.0;
  if (p < 0.5) return lower_normal_quantile(p);
  return -lower_normal_quantile(1.0 - p);  // exact: 1 - p is representable for p in (1/2, 1)
}

double regularized_gamma_q(double a, double x) {
  require_positive_finite("regularized_gamma_q", "a", a);
  if (std::isnan(x) || x < 0.0) fail("regularized_gamma_q", fmt::format("x must be >= 0, got {}", x));
  if (std::isinf(x)) return 0.0;
  return regularized_gamma(a, x).second;
}

double chi2_sf(double x, double dof) {
  require_positive_finite("chi2_sf", "dof", dof);
  require_not_nan("chi2_sf", "x", x);
  if (x <= 0.0) return 1.0;
  if (std::isinf(x)) return 0.0;
  return regularized_gamma(0.5 * dof, 0.5 * x).second;
}

double regularized_beta(double a, double b, double x) {
  require_positive_finite("regularized_beta", "a", a);
  require_positive_finite("regularized_beta", "b", b);
  if (!(x >= 0.0 && x <= 1.0)) fail("regularized_beta", fmt::format("x must be in [0, 1], got {}", x));
  return regularized_beta_pair(a, b, x, 1.0 - x).first;
}

double f_sf(double f, double d1, double d2) {
  require_positive_finite("f_sf", "d1", d1);
  require_positive_finite("f_sf", "d2", d2);
  require_not_nan("f_sf", "f", f);
  if (f <= 0.0) return 1.0;
  const double d1f = d1 * f;
  if (std::isinf(d1f)) return 0.0;
  const double sum = d2 + d1f;
  return regularized_beta_pair(0.5 * d2, 0.5 * d1, d2 / sum, d1f / sum).first;
}

double student_t_two_sided_p(double t, double dof) {
  require_positive_finite("student_t_two_sided_p", "dof", dof);
  require_not_nan("student_t_two_sided_p", "t", t);
  const double t2 = t * t;
  if (std::isinf(t2)) return 0.0;
  const double sum = dof + t2;
  return regularized_beta_pair(0.5 * dof, 0.5, dof / sum, t2 / sum).first;
}

std::vector<double> autocorrelation(std::span<const double> x, int max_lag) {
  constexpr const char* function = "autocorrelation";
  require_min_size(function, "x", x, 2);
  require_lag(function, "max_lag", max_lag, 0, x.size());
  require_finite_samples(function, "x", x);
  require_not_constant(function, "x", x);
  const std::vector<double> d = deviations(x);
  const double c0 = sum_of_squares(d);
  if (!(c0 > 0.0)) fail(function, "x has zero variance");
  const auto lags = static_cast<std::size_t>(max_lag);
  std::vector<double> r(lags + 1);
  r[0] = 1.0;
  for (std::size_t k = 1; k <= lags; ++k) {
    double ck = 0.0;
    for (std::size_t t = k; t < d.size(); ++t) ck += d[t] * d[t - k];
    r[k] = ck / c0;
  }
  return r;
}

std::vector<double> cross_correlation(std::span<const double> e, std::span<const double> u, int max_lag) {
  constexpr const char* function = "cross_correlation";
  if (e.size() != u.size()) {
    fail(function, fmt::format("e and u must have equal lengths, got {} and {}", e.size(), u.size()));
  }
  require_min_size(function, "e", e, 2);
  require_lag(function, "max_lag", max_lag, 0, e.size());
  require_finite_samples(function, "e", e);
  require_finite_samples(function, "u", u);
  require_not_constant(function, "e", e);
  require_not_constant(function, "u", u);
  const std::vector<double> de = deviations(e);
  const std::vector<double> du = deviations(u);
  const double scale = std::sqrt(sum_of_squares(de) * sum_of_squares(du));  // N sigma_e sigma_u
  if (!(scale > 0.0)) fail(function, "e or u has zero variance");
  const std::size_t n = de.size();
  const auto lags = static_cast<std::size_t>(max_lag);
  std::vector<double> r(2 * lags + 1);
  for (std::size_t k = 0; k <= lags; ++k) {
    double positive = 0.0;  // sum_t e(t) u(t - k)
    double negative = 0.0;  // sum_t e(t) u(t + k)
    for (std::size_t t = k; t < n; ++t) positive += de[t] * du[t - k];
    for (std::size_t t = 0; t + k < n; ++t) negative += de[t] * du[t + k];
    r[lags + k] = positive / scale;
    r[lags - k] = negative / scale;
  }
  return r;
}

double correlation_band(std::size_t n, double confidence) {
  if (n == 0) fail("correlation_band", "n must be >= 1");
  if (!(confidence > 0.0 && confidence < 1.0)) {
    fail("correlation_band", fmt::format("confidence must be in (0, 1), got {}", confidence));
  }
  return normal_quantile(0.5 * (1.0 + confidence)) / std::sqrt(static_cast<double>(n));
}

PortmanteauTest ljung_box(std::span<const double> e, int lags) {
  constexpr const char* function = "ljung_box";
  require_min_size(function, "e", e, 2);
  require_lag(function, "lags", lags, 1, e.size());
  const std::vector<double> r = autocorrelation(e, lags);
  const auto n = static_cast<double>(e.size());
  double sum = 0.0;
  for (std::size_t k = 1; k < r.size(); ++k) sum += r[k] * r[k] / (n - static_cast<double>(k));
  const double q = n * (n + 2.0) * sum;
  return {q, lags, chi2_sf(q, static_cast<double>(lags))};
}

PortmanteauTest cross_correlation_test(std::span<const double> e, std::span<const double> u, int lags) {
  const std::vector<double> r = cross_correlation(e, u, lags);
  double sum = 0.0;
  for (std::size_t k = static_cast<std::size_t>(lags); k < r.size(); ++k) sum += r[k] * r[k];
  const double s = static_cast<double>(e.size()) * sum;
  return {s, lags + 1, chi2_sf(s, static_cast<double>(lags + 1))};
}

PortmanteauTest cross_correlation_test_colored_input(std::span<const double> e, std::span<const double> u,
                                                      int lags) {
  constexpr const char* function = "cross_correlation_test_colored_input";
  const std::vector<double> r_eu = cross_correlation(e, u, lags);
  const std::vector<double> r_u = autocorrelation(u, lags);
  const std::size_t m = static_cast<std::size_t>(lags) + 1;
  // Cholesky factor L (row-major, lower) of the Toeplitz R_u(i, j) = r_u(|i - j|).
  std::vector<double> l(m * m, 0.0);
  for (std::size_t i = 0; i < m; ++i) {
    for (std::size_t j = 0; j <= i; ++j) {
      double s = r_u[i - j];
      for (std::size_t k = 0; k < j; ++k) s -= l[i * m + k] * l[j * m + k];
      if (i == j) {
        // R_u has a unit diagonal, so the pivots are relative: 1e-10 means a condition number beyond ~1e10.
        if (!(s > 1e-10)) {
          fail(function, fmt::format("the input autocorrelation matrix is numerically singular at lag {} "
                                     "(pivot {}); use fewer lags or a richer input",
                                     i, s));
        }
        l[i * m + i] = std::sqrt(s);
      } else {
        l[i * m + j] = s / l[j * m + j];
      }
    }
  }
  // zeta = N r^T R_u^{-1} r = N |L^{-1} r|^2.
  std::vector<double> z(m);
  double sum = 0.0;
  for (std::size_t i = 0; i < m; ++i) {
    double s = r_eu[static_cast<std::size_t>(lags) + i];
    for (std::size_t k = 0; k < i; ++k) s -= l[i * m + k] * z[k];
    z[i] = s / l[i * m + i];
    sum += z[i] * z[i];
  }
  const double zeta = static_cast<double>(e.size()) * sum;
  return {zeta, lags + 1, chi2_sf(zeta, static_cast<double>(lags + 1))};
}

TrendTest linear_trend(std::span<const double> y) {
  constexpr const char* function = "linear_trend";
  require_min_size(function, "y", y, 3);
  require_finite_samples(function, "y", y);
  const auto n = static_cast<double>(y.size());
  const double t_mean = 0.5 * (n - 1.0);
  const double stt = n * (n * n - 1.0) / 12.0;  // sum_{t=0}^{N-1} (t - tbar)^2
  const double y_mean = mean(y);
  double sty = 0.0;
  for (std::size_t i = 0; i < y.size(); ++i) sty += (static_cast<double>(i) - t_mean) * (y[i] - y_mean);
  const double slope = sty / stt;
  const double intercept = y_mean - slope * t_mean;
  double rss = 0.0;
  for (std::size_t i = 0; i < y.size(); ++i) {
    const double residual = y[i] - (intercept + slope * static_cast<double>(i));
    rss += residual * residual;
  }
  const double dof = n - 2.0;
  const double std_error = std::sqrt(rss / dof / stt);
  if (std_error == 0.0) {
    if (slope == 0.0) return {slope, intercept, 0.0, 0.0, 1.0};
    return {slope, intercept, 0.0, std::copysign(infinity, slope), 0.0};
  }
  const double t = slope / std_error;
  return {slope, intercept, std_error, t, student_t_two_sided_p(t, dof)};
}

double fit_percent(std::span<const double> measured, std::span<const double> simulated) {
  constexpr const char* function = "fit_percent";
  if (measured.size() != simulated.size()) {
    fail(function, fmt::format("measured and simulated must have equal lengths, got {} and {}", measured.size(),
                               simulated.size()));
  }
  require_min_size(function, "measured", measured, 2);
  require_finite_samples(function, "measured", measured);
  require_finite_samples(function, "simulated", simulated);
  require_not_constant(function, "measured", measured);
  const double norm_about_mean = std::sqrt(sum_of_squares(deviations(measured)));
  if (!(norm_about_mean > 0.0)) fail(function, "measured has zero variance");
  double error = 0.0;
  for (std::size_t i = 0; i < measured.size(); ++i) {
    const double d = measured[i] - simulated[i];
    error += d * d;
  }
  return 100.0 * (1.0 - std::sqrt(error) / norm_about_mean);
}

}  // namespace lashid::sim::stats
