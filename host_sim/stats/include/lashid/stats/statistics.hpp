// Residual statistics for the diagnosis of measured data: distribution tails (normal, chi-square, Fisher F,
// Student t), sample auto- and cross-correlations, the Ljung-Box whiteness test, the residual/input
// independence test and a linear-trend test. The fit percentage and the median are in metrics.hpp (included).
//
// The special functions and distribution tails are Boost.Math's (boost/math/distributions, special_functions);
// this header keeps the project's interface to them: plain double, tails that underflow return 0, and bad
// arguments (too short series, lags out of range, non-positive degrees of freedom, probabilities outside (0, 1),
// NaN, non-finite samples) throw std::invalid_argument with a message naming the function and the offending value.
// A Boost series that does not converge (not expected) throws boost::math::evaluation_error, a std::runtime_error.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "lashid/stats/metrics.hpp"

namespace lashid::sim::stats {

// ---------------------------------------------------------------------------------------------------------
// Distributions
// ---------------------------------------------------------------------------------------------------------

// Standard normal CDF, Phi(z) = erfc(-z / sqrt(2)) / 2 (Abramowitz & Stegun 26.2.2 with 7.1.2), std::erfc.
// Accurate to a few ulp in relative terms also deep in the lower tail. Throws for NaN; Phi(-inf) = 0,
// Phi(+inf) = 1.
double normal_cdf(double z);

// Standard normal quantile Phi^{-1}(p), p in (0, 1) (open interval; throws otherwise). Boost's normal quantile
// (an inverse erfc accurate to a few ulp), evaluated on the lower tail (p < 1/2) and mirrored, so
// normal_quantile(1 - p) == -normal_quantile(p) exactly and the result stays accurate for p down to the smallest
// normal doubles. For p near 1 the accuracy is limited by the representation of 1 - p, not by the method.
double normal_quantile(double p);

// Upper regularized incomplete gamma function Q(a, x) = Gamma(a, x) / Gamma(a) (Abramowitz & Stegun 6.5),
// a > 0, x >= 0 (x = +inf gives 0); boost::math::gamma_q, relatively accurate also deep in the upper tail.
double regularized_gamma_q(double a, double x);

// Chi-square survival function P(X > x) for X ~ chi2(dof), = Q(dof / 2, x / 2) (A&S 26.4.19). dof > 0 (real
// allowed); x <= 0 gives 1, x = +inf gives 0.
double chi2_sf(double x, double dof);

// Regularized incomplete beta function I_x(a, b) = B(x; a, b) / B(a, b) (A&S 6.6), a > 0, b > 0, x in [0, 1];
// boost::math::ibeta.
double regularized_beta(double a, double b, double x);

// Upper tail of Fisher's F distribution with (d1, d2) degrees of freedom, P(F > f) =
// I_{d2 / (d2 + d1 f)}(d2 / 2, d1 / 2) (A&S 26.6.2). d1, d2 > 0; f <= 0 gives 1; f = +inf gives 0. Boost forms
// the argument of the incomplete beta without cancellation, so small p-values keep their relative accuracy.
double f_sf(double f, double d1, double d2);

// Two-sided p-value of Student's t with dof > 0 degrees of freedom, P(|T| > |t|) =
// I_{dof / (dof + t^2)}(dof / 2, 1 / 2) (A&S 26.7.1 with 26.5.27). t = +-inf gives 0. Note
// f_sf(t^2, 1, dof) == student_t_two_sided_p(t, dof) up to rounding.
double student_t_two_sided_p(double t, double dof);

// ---------------------------------------------------------------------------------------------------------
// Sample correlations
// ---------------------------------------------------------------------------------------------------------

// Sample autocorrelation of the mean-removed series, biased estimator (Box, Jenkins & Reinsel, "Time Series
// Analysis", §2.1.5; Ljung 1999 §16.6):
//   r(k) = c(k) / c(0),  c(k) = (1/N) sum_{t=k}^{N-1} (x(t) - xbar)(x(t-k) - xbar),  k = 0..max_lag,
// so r(0) = 1 and the sequence is positive semi-definite. Requires N >= 2, 0 <= max_lag < N, finite
// samples and a non-zero variance (throws otherwise). Returns max_lag + 1 values.
std::vector<double> autocorrelation(std::span<const double> x, int max_lag);

// Sample cross-correlation of e and u (equal lengths N >= 2, both with non-zero variance):
//   r_eu(k) = sum_t (e(t) - ebar)(u(t-k) - ubar) / (N sigma_e sigma_u),  k = -max_lag..max_lag,
// the sum over the t for which both samples exist, sigma the biased (1/N) standard deviations. Positive k
// means u leads e (e.g. e(t) = u(t - 3) peaks at k = +3). Returned with index k + max_lag (size
// 2 max_lag + 1). Requires 0 <= max_lag < N.
std::vector<double> cross_correlation(std::span<const double> e, std::span<const double> u, int max_lag);

// The part of x that does not repeat with a period: x(i) minus the mean of the samples of x at the same phase,
// t(i) mod period (the synchronous average over the periods of a periodic experiment, which keeps the periodic
// response and averages the noise out; Pintelon & Schoukens, "System Identification: A Frequency Domain
// Approach", 2nd ed., Wiley-IEEE Press 2012, on periodic excitations). t(i) is the sample index of x(i) (gaps
// allowed); period 1 removes the mean. Requires x and t of equal length and period >= 1 (throws otherwise).
std::vector<double> without_periodic_mean(std::span<const double> x, std::span<const std::size_t> t,
                                          std::size_t period);

// Approximate two-sided confidence band for a sample (auto- or cross-) correlation of a white series:
// +- normal_quantile((1 + confidence) / 2) / sqrt(n) (Ljung 1999 §16.6, from sqrt(N) r(k) -> N(0, 1)).
// n >= 1, confidence in (0, 1). For a cross-correlation the band assumes one of the two series is white.
double correlation_band(std::size_t n, double confidence);

// ---------------------------------------------------------------------------------------------------------
// Tests
// ---------------------------------------------------------------------------------------------------------

struct PortmanteauTest {
  double statistic;  // the chi-square-distributed statistic under the null hypothesis
  int dof;           // its degrees of freedom
  double p_value;    // chi2_sf(statistic, dof): small means "reject the null hypothesis"
};

// Ljung-Box whiteness test of the residuals e (Ljung & Box, Biometrika 65(2), 1978):
//   Q = N (N + 2) sum_{k=1}^{lags} r(k)^2 / (N - k),  r = autocorrelation(e, lags),  dof = lags,
// H0: e is white. Requires 1 <= lags < N (and the autocorrelation's preconditions). When e are residuals of
// a model with p estimated ARMA-type parameters, the exact dof would be lags - p; this function does not
// subtract them (a conservative p-value for the usual output-error residuals).
PortmanteauTest ljung_box(std::span<const double> e, int lags);

// Independence test of the residuals e and the input u (Ljung, "System Identification", 2nd ed. 1999,
// §16.6, simplified form):
//   S = N sum_{k=0}^{lags} r_eu(k)^2,  r_eu = cross_correlation(e, u, lags),  dof = lags + 1,
// H0: e(t) is uncorrelated with the past and present inputs u(t), u(t-1), ..., u(t-lags).
// Assumption: the chi2(lags + 1) distribution holds when the lagged correlations sqrt(N) r_eu(k) are
// uncorrelated unit-variance normals; the variance is 1 when one of the two series is white, and the lags
// are uncorrelated only when additionally the other one is (nearly) white at lags <= `lags`. With a white e
// and a strongly autocorrelated (slow) input, the statistic keeps its mean lags + 1 but is over-dispersed and
// the test rejects too often; use cross_correlation_test_colored_input then, or pre-whiten u.
// Requires 0 <= lags < N.
PortmanteauTest cross_correlation_test(std::span<const double> e, std::span<const double> u, int lags);

// The same hypothesis with Ljung's full statistic (1999, §16.6), valid for an arbitrarily autocorrelated u
// provided e is white under H0:
//   zeta = N r^T R_u^{-1} r,  r = (r_eu(0), ..., r_eu(lags)),  R_u(i, j) = r_u(|i - j|) (Toeplitz of
//   autocorrelation(u, lags)),  dof = lags + 1.
// Since sqrt(N) r is asymptotically N(0, R_u) when e is white and independent of u, zeta -> chi2(lags + 1).
// Reduces to cross_correlation_test when u is white. Throws std::invalid_argument if R_u is numerically
// singular (e.g. a pure sinusoid with lags + 1 exceeding its two-dimensional span), and the preconditions of
// cross_correlation_test.
PortmanteauTest cross_correlation_test_colored_input(std::span<const double> e, std::span<const double> u,
                                                      int lags);

struct TrendTest {
  double slope;            // b in y(t) = a + b t + residual, t = 0..N-1 (units of y per sample)
  double intercept;        // a
  double slope_std_error;  // se(b) = sqrt(s^2 / sum (t - tbar)^2), s^2 = RSS / (N - 2)
  double t;                // b / se(b); +-inf for an exact non-constant line, 0 for a constant series
  double p_value;          // two-sided, Student t with N - 2 dof (0 for an exact line, 1 for a constant)
};

// Ordinary least squares of y on (1, t), t = 0..N-1, and the two-sided t-test of H0: slope = 0 (any
// regression text, e.g. Draper & Smith, "Applied Regression Analysis", ch. 1). Requires N >= 3 and finite y.
// The residuals are assumed white; for autocorrelated residuals the p-value is too small.
TrendTest linear_trend(std::span<const double> y);

}  // namespace lashid::sim::stats
