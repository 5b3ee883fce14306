// Residual statistics: see statistics.hpp for the formulas and references. The special functions and distribution
// tails are Boost.Math's; the arguments are checked here first, so that bad input gets this layer's
// std::invalid_argument rather than Boost's std::domain_error.
#include "lashid/stats/statistics.hpp"

#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/fisher_f.hpp>
#include <boost/math/distributions/normal.hpp>
#include <boost/math/distributions/students_t.hpp>
#include <boost/math/special_functions/beta.hpp>
#include <boost/math/special_functions/gamma.hpp>
#include <fmt/format.h>

#include <cmath>
#include <cstddef>
#include <limits>
#include <numbers>

#include "arguments.hpp"

namespace lashid::sim::stats {

namespace {

using detail::fail;
using detail::require_finite_samples;
using detail::require_min_size;
using detail::require_not_constant;
using detail::require_not_nan;
using detail::require_positive_finite;

constexpr double infinity = std::numeric_limits<double>::infinity();

namespace policies = boost::math::policies;
// Error policy of every Boost.Math call here. The arguments are validated before the call, so a domain or pole
// error would be a bug of this file and keeps Boost's default (throw). A tail probability too small for a double is
// 0, not an error. An intermediate too large for a double (e.g. Gamma(a) for a chi-square with 1e5 degrees of
// freedom, divided into x^a e^-x) is +inf and the probability is still right, so overflow is not an error either.
// A series that does not converge throws boost::math::evaluation_error, a std::runtime_error.
using Policy = policies::policy<policies::underflow_error<policies::ignore_error>,
                                policies::overflow_error<policies::ignore_error>,
                                policies::evaluation_error<policies::throw_on_error>>;

// 1 - I_z(1/2, 1/2) for z <= 1/2, where I_z(1/2, 1/2) <= 1/2, so the difference is exact to an ulp. The upper tail
// of the arcsine case, which the Student t with one degree of freedom (|t| < 1/sqrt(2)) and F(1, 1) (f <= 1)
// reach: Boost 1.74's ibetac(1/2, 1/2, z) takes asin(sqrt(1 - z)), losing up to 1e-10 (absolute) for small z and
// returning exactly 1 below z ~ 1e-20 (its cdf of the Cauchy distribution at t = -1e-10 is 0.5).
double arcsine_upper_tail(double z) { return 1.0 - boost::math::ibeta(0.5, 0.5, z, Policy()); }

// 0 <= lag < n.
void require_lag(const char* function, const char* name, int lag, int min_lag, std::size_t n) {
  if (lag < min_lag || static_cast<std::size_t>(lag) >= n) {
    fail(function, fmt::format("{} must be in [{}, N - 1] = [{}, {}], got {}", name, min_lag, min_lag, n - 1, lag));
  }
}

}  // namespace

double normal_cdf(double z) {
  require_not_nan("normal_cdf", "z", z);
  return 0.5 * std::erfc(-z * (0.5 * std::numbers::sqrt2));
}

double normal_quantile(double p) {
  if (!(p > 0.0 && p < 1.0)) fail("normal_quantile", fmt::format("p must be in (0, 1), got {}", p));
  if (p == 0.5) return 0.0;
  const boost::math::normal_distribution<double, Policy> standard;
  if (p < 0.5) return boost::math::quantile(standard, p);
  // Mirrored: 1 - p is exact for p in (1/2, 1), and quantile(1 - p) == -quantile(p) holds to the bit.
  return -boost::math::quantile(standard, 1.0 - p);
}

double regularized_gamma_q(double a, double x) {
  require_positive_finite("regularized_gamma_q", "a", a);
  if (std::isnan(x) || x < 0.0) fail("regularized_gamma_q", fmt::format("x must be >= 0, got {}", x));
  if (std::isinf(x)) return 0.0;
  return boost::math::gamma_q(a, x, Policy());
}

double chi2_sf(double x, double dof) {
  require_positive_finite("chi2_sf", "dof", dof);
  require_not_nan("chi2_sf", "x", x);
  if (x <= 0.0) return 1.0;
  if (std::isinf(x)) return 0.0;
  return boost::math::cdf(boost::math::complement(boost::math::chi_squared_distribution<double, Policy>(dof), x));
}

double regularized_beta(double a, double b, double x) {
  require_positive_finite("regularized_beta", "a", a);
  require_positive_finite("regularized_beta", "b", b);
  if (!(x >= 0.0 && x <= 1.0)) fail("regularized_beta", fmt::format("x must be in [0, 1], got {}", x));
  return boost::math::ibeta(a, b, x, Policy());
}

double f_sf(double f, double d1, double d2) {
  require_positive_finite("f_sf", "d1", d1);
  require_positive_finite("f_sf", "d2", d2);
  require_not_nan("f_sf", "f", f);
  if (f <= 0.0) return 1.0;
  if (std::isinf(f)) return 0.0;
  if (d1 == 1.0 && d2 == 1.0 && f <= 1.0) return arcsine_upper_tail(f / (1.0 + f));
  return boost::math::cdf(boost::math::complement(boost::math::fisher_f_distribution<double, Policy>(d1, d2), f));
}

double student_t_two_sided_p(double t, double dof) {
  require_positive_finite("student_t_two_sided_p", "dof", dof);
  require_not_nan("student_t_two_sided_p", "t", t);
  if (std::isinf(t)) return 0.0;
  if (dof == 1.0 && 2.0 * t * t < 1.0) return arcsine_upper_tail(t * t / (1.0 + t * t));
  // 2 P(T < -|t|): the lower tail is formed without cancellation, and doubling it is exact.
  return 2.0 * boost::math::cdf(boost::math::students_t_distribution<double, Policy>(dof), -std::fabs(t));
}

std::vector<double> autocorrelation(std::span<const double> x, int max_lag) {
  constexpr const char* function = "autocorrelation";
  require_min_size(function, "x", x, 2);
  require_lag(function, "max_lag", max_lag, 0, x.size());
  require_finite_samples(function, "x", x);
  require_not_constant(function, "x", x);
  const std::vector<double> d = detail::deviations(x);
  const double c0 = detail::sum_of_squares(d);
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

std::vector<double> without_periodic_mean(std::span<const double> x, std::span<const std::size_t> t,
                                          std::size_t period) {
  constexpr const char* function = "without_periodic_mean";
  if (x.size() != t.size()) fail(function, fmt::format("x has {} samples but t {}", x.size(), t.size()));
  if (period < 1) fail(function, "period must be at least 1");
  std::vector<double> mean(period, 0.0);
  std::vector<std::size_t> count(period, 0);
  for (std::size_t i = 0; i < x.size(); ++i) {
    mean[t[i] % period] += x[i];
    ++count[t[i] % period];
  }
  for (std::size_t k = 0; k < period; ++k) {
    if (count[k] > 0) mean[k] /= static_cast<double>(count[k]);
  }
  std::vector<double> out(x.begin(), x.end());
  for (std::size_t i = 0; i < x.size(); ++i) out[i] -= mean[t[i] % period];
  return out;
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
  const std::vector<double> de = detail::deviations(e);
  const std::vector<double> du = detail::deviations(u);
  const double scale = std::sqrt(detail::sum_of_squares(de) * detail::sum_of_squares(du));  // N sigma_e sigma_u
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
  const double y_mean = detail::mean(y);
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

}  // namespace lashid::sim::stats
