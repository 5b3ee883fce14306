// Correlations, residual tests, trend, fit and median of the statistics layer against hand-computed values,
// closed forms and the null distributions they claim.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "lashid/plant/linear_plant.hpp"
#include "lashid/stats/metrics.hpp"
#include "lashid/stats/statistics.hpp"
#include "statistics_support.hpp"

namespace lashid::sim::stats {
namespace {

using test::inf;
using test::nan;
using test::relatively_near;

std::vector<double> white_noise(std::size_t n, std::uint64_t seed) {
  GaussianNoise noise(1.0, seed);
  std::vector<double> x(n);
  for (double& v : x) v = noise.next();
  return x;
}

std::vector<double> ar1(std::size_t n, double phi, std::uint64_t seed) {
  GaussianNoise noise(1.0, seed);
  std::vector<double> x(n);
  // Start in the stationary distribution, variance 1 / (1 - phi^2).
  double previous = noise.next() / std::sqrt(1.0 - phi * phi);
  for (double& v : x) {
    v = phi * previous + noise.next();
    previous = v;
  }
  return x;
}

// ---------------------------------------------------------------------------------------------------------

TEST(Autocorrelation, HandComputedAlternatingSeries) {
  // x = (1, -1, 1, -1): mean 0, c0 = 4, r(1) = -3/4, r(2) = 2/4, r(3) = -1/4.
  const std::vector<double> x{1.0, -1.0, 1.0, -1.0};
  const std::vector<double> r = autocorrelation(x, 3);
  ASSERT_EQ(r.size(), 4u);
  EXPECT_DOUBLE_EQ(r[0], 1.0);
  EXPECT_DOUBLE_EQ(r[1], -0.75);
  EXPECT_DOUBLE_EQ(r[2], 0.5);
  EXPECT_DOUBLE_EQ(r[3], -0.25);
  // Removing the mean: an offset changes nothing.
  const std::vector<double> shifted{11.0, 9.0, 11.0, 9.0};
  const std::vector<double> rs = autocorrelation(shifted, 3);
  for (std::size_t k = 0; k < 4; ++k) EXPECT_NEAR(rs[k], r[k], 1e-15) << k;
}

TEST(Autocorrelation, Ar1MatchesPhiToTheLag) {
  const std::vector<double> x = ar1(200000, 0.6, 7);
  const std::vector<double> r = autocorrelation(x, 3);
  EXPECT_EQ(r[0], 1.0);
  EXPECT_NEAR(r[1], 0.6, 0.01);
  EXPECT_NEAR(r[2], 0.36, 0.01);
  EXPECT_NEAR(r[3], 0.216, 0.01);
}

TEST(Autocorrelation, RejectsBadArguments) {
  const std::vector<double> x{1.0, 2.0, 4.0};
  EXPECT_THROW(autocorrelation(x, 3), std::invalid_argument);
  EXPECT_THROW(autocorrelation(x, -1), std::invalid_argument);
  EXPECT_THROW(autocorrelation(std::vector<double>{1.0}, 0), std::invalid_argument);
  EXPECT_THROW(autocorrelation(std::vector<double>{0.1, 0.1, 0.1}, 1), std::invalid_argument);
  EXPECT_THROW(autocorrelation(std::vector<double>{1.0, nan, 2.0}, 1), std::invalid_argument);
  EXPECT_NO_THROW(autocorrelation(x, 2));
}

TEST(CrossCorrelation, HandComputed) {
  // e = (1, 0, -1), u = (0, 1, -1): both zero mean, sum e^2 = sum u^2 = 2, so r = (sum) / 2.
  // k = 0: 1; k = 1: e(1)u(0) + e(2)u(1) = -1; k = -1: e(0)u(1) + e(1)u(2) = 1; k = 2: e(2)u(0) = 0;
  // k = -2: e(0)u(2) = -1.
  const std::vector<double> e{1.0, 0.0, -1.0};
  const std::vector<double> u{0.0, 1.0, -1.0};
  const std::vector<double> r = cross_correlation(e, u, 2);
  ASSERT_EQ(r.size(), 5u);
  EXPECT_DOUBLE_EQ(r[0], -0.5);  // k = -2
  EXPECT_DOUBLE_EQ(r[1], 0.5);   // k = -1
  EXPECT_DOUBLE_EQ(r[2], 0.5);   // k = 0
  EXPECT_DOUBLE_EQ(r[3], -0.5);  // k = 1
  EXPECT_DOUBLE_EQ(r[4], 0.0);   // k = 2
}

TEST(CrossCorrelation, DelayedCopyPeaksAtTheDelay) {
  constexpr std::size_t n = 5000;
  constexpr int max_lag = 10;
  const std::vector<double> w = white_noise(n + 3, 11);
  // e(t) = w(t), u(t) = w(t + 3), so e(t) = u(t - 3).
  const std::vector<double> e(w.begin(), w.begin() + n);
  const std::vector<double> u(w.begin() + 3, w.end());
  const std::vector<double> r = cross_correlation(e, u, max_lag);
  ASSERT_EQ(r.size(), 2u * max_lag + 1);
  const double band = 4.0 / std::sqrt(static_cast<double>(n));
  for (int k = -max_lag; k <= max_lag; ++k) {
    const double value = r[static_cast<std::size_t>(k + max_lag)];
    if (k == 3) {
      EXPECT_NEAR(value, 1.0, 0.01);
    } else {
      EXPECT_LT(std::fabs(value), band) << "k = " << k;
    }
  }
}

TEST(CrossCorrelation, RejectsBadArguments) {
  const std::vector<double> e{1.0, 2.0, 4.0};
  EXPECT_THROW(cross_correlation(e, std::vector<double>{1.0, 2.0}, 0), std::invalid_argument);
  EXPECT_THROW(cross_correlation(e, std::vector<double>{3.0, 3.0, 3.0}, 0), std::invalid_argument);
  EXPECT_THROW(cross_correlation(e, std::vector<double>{3.0, 1.0, 2.0}, 3), std::invalid_argument);
  EXPECT_THROW(cross_correlation(e, std::vector<double>{3.0, 1.0, 2.0}, -1), std::invalid_argument);
  EXPECT_THROW(cross_correlation(e, std::vector<double>{3.0, inf, 2.0}, 1), std::invalid_argument);
}

TEST(CorrelationBand, NormalQuantileOverRootN) {
  EXPECT_TRUE(relatively_near(correlation_band(100, 0.95), 0.1959963984540054, 1e-14));
  EXPECT_TRUE(relatively_near(correlation_band(4, 0.99), 2.5758293035489 / 2.0, 1e-13));
  EXPECT_THROW(correlation_band(0, 0.95), std::invalid_argument);
  EXPECT_THROW(correlation_band(10, 1.0), std::invalid_argument);
  EXPECT_THROW(correlation_band(10, 0.0), std::invalid_argument);
}

TEST(WithoutPeriodicMean, HandComputedWithGaps) {
  // Period 3, indices with a gap (t = 4 missing): phase 0 holds x at t = 0, 3, 6 (1, 4, 7: mean 4), phase 1 at
  // t = 1, 7 (2, 9: mean 5.5), phase 2 at t = 2, 5 (3, 8: mean 5.5).
  const std::vector<double> x{1, 2, 3, 4, 8, 7, 9};
  const std::vector<std::size_t> t{0, 1, 2, 3, 5, 6, 7};
  const std::vector<double> out = without_periodic_mean(x, t, 3);
  const std::vector<double> expected{-3, -3.5, -2.5, 0, 2.5, 3, 3.5};
  ASSERT_EQ(out.size(), expected.size());
  for (std::size_t i = 0; i < out.size(); ++i) EXPECT_DOUBLE_EQ(out[i], expected[i]) << i;
  // Period 1: the mean (34 / 7) removed.
  const std::vector<double> centred = without_periodic_mean(x, t, 1);
  for (std::size_t i = 0; i < x.size(); ++i) EXPECT_NEAR(centred[i], x[i] - 34.0 / 7.0, 1e-14) << i;
}

TEST(WithoutPeriodicMean, LeavesTheNoiseOfAPeriodicResponse) {
  // A period-18 response (far larger than the noise) plus AR(1) noise, phi = 0.5. The periodic part dominates the
  // raw autocorrelation; without it, Ljung-Box Q / N is the noise's: N sum_k r(k)^2 / N with r(k) = phi^k, i.e.
  // sum_{k=1}^{20} 0.25^k = (1 - 0.25^20) / 3 (closed form), within sampling error (r(k) +- 1 / sqrt(N)).
  constexpr std::size_t n = 60000;
  constexpr std::size_t period = 18;
  std::vector<double> x = ar1(n, 0.5, 41);
  std::vector<std::size_t> t(n);
  for (std::size_t i = 0; i < n; ++i) {
    t[i] = i;
    x[i] += 5.0 * std::sin(2.0 * std::numbers::pi * static_cast<double>(i % period) / period) +
            (i % period == 4 ? 8.0 : 0.0);
  }
  const double expected = (1.0 - std::pow(0.25, 20)) / 3.0;
  const double raw = ljung_box(x, 20).statistic / static_cast<double>(n);
  const double aperiodic = ljung_box(without_periodic_mean(x, t, period), 20).statistic / static_cast<double>(n);
  EXPECT_GT(raw, 3.0 * expected);
  EXPECT_NEAR(aperiodic, expected, 0.02);
}

TEST(WithoutPeriodicMean, RejectsBadArguments) {
  const std::vector<double> x{1.0, 2.0};
  EXPECT_THROW(without_periodic_mean(x, std::vector<std::size_t>{0}, 1), std::invalid_argument);
  EXPECT_THROW(without_periodic_mean(x, std::vector<std::size_t>{0, 1}, 0), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------------------------

TEST(LjungBox, HandComputedAlternatingSeries) {
  // r(1) = -3/4, r(2) = 1/2, N = 4: Q = 4 * 6 * (9/16 / 3 + 1/4 / 2) = 7.5, chi2(2) tail = exp(-7.5 / 2).
  const std::vector<double> x{1.0, -1.0, 1.0, -1.0};
  const PortmanteauTest test = ljung_box(x, 2);
  EXPECT_DOUBLE_EQ(test.statistic, 7.5);
  EXPECT_EQ(test.dof, 2);
  EXPECT_TRUE(relatively_near(test.p_value, std::exp(-3.75), 1e-13));
}

TEST(LjungBox, WhiteNoisePValuesAreRoughlyUniform) {
  constexpr int series = 400;
  int below_005 = 0;
  int below_050 = 0;
  for (int i = 0; i < series; ++i) {
    const PortmanteauTest test = ljung_box(white_noise(200, 1000 + static_cast<std::uint64_t>(i)), 10);
    below_005 += test.p_value < 0.05 ? 1 : 0;
    below_050 += test.p_value < 0.5 ? 1 : 0;
  }
  const double fraction_005 = below_005 / static_cast<double>(series);
  const double fraction_050 = below_050 / static_cast<double>(series);
  EXPECT_GE(fraction_005, 0.02);
  EXPECT_LE(fraction_005, 0.09);
  EXPECT_GE(fraction_050, 0.42);  // binomial standard deviation 0.025: 3.2 sigma
  EXPECT_LE(fraction_050, 0.58);
}

TEST(LjungBox, DetectsAutocorrelation) {
  EXPECT_LT(ljung_box(ar1(500, 0.5, 5), 10).p_value, 1e-10);
}

TEST(LjungBox, RejectsBadArguments) {
  const std::vector<double> x{1.0, 3.0, 2.0, 5.0};
  EXPECT_THROW(ljung_box(x, 0), std::invalid_argument);
  EXPECT_THROW(ljung_box(x, 4), std::invalid_argument);
  EXPECT_THROW(ljung_box(std::vector<double>{2.0, 2.0, 2.0, 2.0}, 1), std::invalid_argument);
  EXPECT_NO_THROW(ljung_box(x, 3));
}

TEST(CrossCorrelationTest, HandComputed) {
  // From CrossCorrelation.HandComputed: r_eu(0) = 1/2, r_eu(1) = -1/2, N = 3: S = 3 (1/4 + 1/4) = 1.5, dof 2.
  const std::vector<double> e{1.0, 0.0, -1.0};
  const std::vector<double> u{0.0, 1.0, -1.0};
  const PortmanteauTest test = cross_correlation_test(e, u, 1);
  EXPECT_DOUBLE_EQ(test.statistic, 1.5);
  EXPECT_EQ(test.dof, 2);
  EXPECT_TRUE(relatively_near(test.p_value, std::exp(-0.75), 1e-13));
}

TEST(CrossCorrelationTest, ColoredInputHandComputed) {
  // r_u(1) = (u(1)u(0) + u(2)u(1)) / 2 = -1/2; R_u = [[1, -1/2], [-1/2, 1]], r = (1/2, -1/2):
  // r^T R_u^{-1} r = (r0^2 - 2 rho r0 r1 + r1^2) / (1 - rho^2) = (1/4 - 1/4 + 1/4) / (3/4) = 1/3; zeta = 1.
  const std::vector<double> e{1.0, 0.0, -1.0};
  const std::vector<double> u{0.0, 1.0, -1.0};
  const PortmanteauTest test = cross_correlation_test_colored_input(e, u, 1);
  EXPECT_NEAR(test.statistic, 1.0, 1e-14);
  EXPECT_EQ(test.dof, 2);
  EXPECT_TRUE(relatively_near(test.p_value, std::exp(-0.5), 1e-13));
  // With a single lag both statistics are N r_eu(0)^2.
  EXPECT_DOUBLE_EQ(cross_correlation_test_colored_input(e, u, 0).statistic, 0.75);
  EXPECT_DOUBLE_EQ(cross_correlation_test(e, u, 0).statistic, 0.75);
}

TEST(CrossCorrelationTest, IndependentWhiteSeriesGiveRoughlyUniformPValues) {
  constexpr int series = 400;
  int plain = 0;
  int colored = 0;
  for (int i = 0; i < series; ++i) {
    const auto seed = static_cast<std::uint64_t>(i);
    const std::vector<double> e = white_noise(300, 5000 + seed);
    const std::vector<double> u = white_noise(300, 9000 + seed);
    plain += cross_correlation_test(e, u, 8).p_value < 0.05 ? 1 : 0;
    colored += cross_correlation_test_colored_input(e, u, 8).p_value < 0.05 ? 1 : 0;
  }
  EXPECT_GE(plain / static_cast<double>(series), 0.02);
  EXPECT_LE(plain / static_cast<double>(series), 0.09);
  EXPECT_GE(colored / static_cast<double>(series), 0.02);
  EXPECT_LE(colored / static_cast<double>(series), 0.09);
}

TEST(CrossCorrelationTest, SlowInputOverRejectsUnlessTheInputCorrelationIsAccountedFor) {
  // White e, independent strongly autocorrelated u (AR(1), phi = 0.95): the simplified statistic is
  // over-dispersed (documented), Ljung's full statistic stays calibrated.
  constexpr int series = 400;
  int plain = 0;
  int colored = 0;
  for (int i = 0; i < series; ++i) {
    const auto seed = static_cast<std::uint64_t>(i);
    const std::vector<double> e = white_noise(400, 20000 + seed);
    const std::vector<double> u = ar1(400, 0.95, 30000 + seed);
    plain += cross_correlation_test(e, u, 15).p_value < 0.05 ? 1 : 0;
    colored += cross_correlation_test_colored_input(e, u, 15).p_value < 0.05 ? 1 : 0;
  }
  EXPECT_GT(plain / static_cast<double>(series), 0.12);
  EXPECT_GE(colored / static_cast<double>(series), 0.02);
  EXPECT_LE(colored / static_cast<double>(series), 0.09);
}

TEST(CrossCorrelationTest, DetectsAnInputEffectInTheResiduals) {
  const std::vector<double> w = white_noise(501, 3);
  const std::vector<double> noise = white_noise(500, 4);
  std::vector<double> e(500);
  std::vector<double> u(w.begin() + 1, w.end());
  // e(t) = 0.5 u(t - 1) + white: r_eu(1) ~ 0.5 / sqrt(1.25) = 0.45, so S ~ 500 * 0.2 = 100 on 6 dof.
  for (std::size_t t = 0; t < e.size(); ++t) e[t] = 0.5 * w[t] + noise[t];
  EXPECT_LT(cross_correlation_test(e, u, 5).p_value, 1e-10);
  EXPECT_LT(cross_correlation_test_colored_input(e, u, 5).p_value, 1e-10);
}

TEST(CrossCorrelationTest, RejectsBadArguments) {
  const std::vector<double> e{1.0, 3.0, 2.0, 5.0};
  const std::vector<double> u{2.0, 1.0, 2.0, 7.0};
  EXPECT_THROW(cross_correlation_test(e, u, -1), std::invalid_argument);
  EXPECT_THROW(cross_correlation_test(e, u, 4), std::invalid_argument);
  EXPECT_THROW(cross_correlation_test(e, std::vector<double>{1.0, 2.0}, 0), std::invalid_argument);
  EXPECT_THROW(cross_correlation_test_colored_input(e, u, 4), std::invalid_argument);
  EXPECT_THROW(cross_correlation_test_colored_input(e, std::vector<double>{1.0, 1.0, 1.0, 1.0}, 1),
               std::invalid_argument);
}

// ---------------------------------------------------------------------------------------------------------

TEST(LinearTrend, ExactLineIsRecovered) {
  std::vector<double> y(50);
  for (std::size_t t = 0; t < y.size(); ++t) y[t] = 2.0 + 0.5 * static_cast<double>(t);
  const TrendTest trend = linear_trend(y);
  EXPECT_NEAR(trend.slope, 0.5, 1e-13);
  EXPECT_NEAR(trend.intercept, 2.0, 1e-12);
  EXPECT_LT(trend.slope_std_error, 1e-12);
  EXPECT_GT(trend.t, 1e9);
  EXPECT_LT(trend.p_value, 1e-12);
}

TEST(LinearTrend, HandComputed) {
  // y = (0, 2, 1, 3): tbar = 1.5, Stt = 5, ybar = 1.5, Sty = 4, slope 0.8, intercept 0.3; residuals
  // (-0.3, 0.9, -0.9, 0.3), RSS = 1.8, s^2 = 0.9, se = sqrt(0.18), t = 0.8 / sqrt(0.18);
  // 2 dof: p = 1 - |t| / sqrt(2 + t^2) = 1 - sqrt(0.64) = 0.2.
  const std::vector<double> y{0.0, 2.0, 1.0, 3.0};
  const TrendTest trend = linear_trend(y);
  EXPECT_NEAR(trend.slope, 0.8, 1e-15);
  EXPECT_NEAR(trend.intercept, 0.3, 1e-15);
  EXPECT_NEAR(trend.slope_std_error, std::sqrt(0.18), 1e-15);
  EXPECT_NEAR(trend.t, 0.8 / std::sqrt(0.18), 1e-14);
  EXPECT_NEAR(trend.p_value, 0.2, 1e-14);
}

TEST(LinearTrend, ConstantSeriesHasNoTrend) {
  const TrendTest trend = linear_trend(std::vector<double>{4.0, 4.0, 4.0, 4.0, 4.0});
  EXPECT_EQ(trend.slope, 0.0);
  EXPECT_EQ(trend.intercept, 4.0);
  EXPECT_EQ(trend.t, 0.0);
  EXPECT_EQ(trend.p_value, 1.0);
}

TEST(LinearTrend, RejectsBadArguments) {
  EXPECT_THROW(linear_trend(std::vector<double>{1.0, 2.0}), std::invalid_argument);
  EXPECT_THROW(linear_trend(std::vector<double>{1.0, nan, 2.0}), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------------------------

TEST(FitPercent, PerfectMeanAndHandComputed) {
  const std::vector<double> y{0.0, 2.0};
  EXPECT_DOUBLE_EQ(fit_percent(y, y), 100.0);
  EXPECT_DOUBLE_EQ(fit_percent(y, std::vector<double>{1.0, 1.0}), 0.0);
  // ||y - yhat|| = sqrt(0.5), ||y - mean|| = sqrt(2): 100 (1 - 1/2) = 50.
  EXPECT_DOUBLE_EQ(fit_percent(y, std::vector<double>{0.5, 1.5}), 50.0);
  // Worse than the mean: ||y - 0|| = 2: 100 (1 - sqrt(2)).
  EXPECT_NEAR(fit_percent(y, std::vector<double>{0.0, 0.0}), 100.0 * (1.0 - std::numbers::sqrt2), 1e-12);
}

TEST(FitPercent, RejectsBadArguments) {
  EXPECT_THROW(fit_percent(std::vector<double>{1.0, 2.0}, std::vector<double>{1.0}), std::invalid_argument);
  EXPECT_THROW(fit_percent(std::vector<double>{3.0, 3.0}, std::vector<double>{1.0, 2.0}), std::invalid_argument);
  EXPECT_THROW(fit_percent(std::vector<double>{1.0}, std::vector<double>{1.0}), std::invalid_argument);
  EXPECT_THROW(fit_percent(std::vector<double>{1.0, 2.0}, std::vector<double>{nan, 2.0}), std::invalid_argument);
}

TEST(Median, OddAndEvenSizes) {
  EXPECT_EQ(median(std::vector<double>{3.0, 1.0, 2.0}), 2.0);
  EXPECT_EQ(median(std::vector<double>{4.0, 1.0, 3.0, 2.0}), 2.5);  // mean of the two middle values
  EXPECT_EQ(median(std::vector<double>{-1.0, 7.0}), 3.0);
  EXPECT_EQ(median(std::vector<double>{5.0}), 5.0);
  EXPECT_EQ(median(std::vector<double>{2.0, 9.0, 2.0, 1.0}), 2.0);
  // An even count: the mean of the two middle values (median takes a span of const: the caller's order is kept by
  // its type, nothing to test at run time).
  const std::vector<double> x{5.0, 3.0, 1.0, 4.0, 2.0, 6.0};
  EXPECT_EQ(median(x), 3.5);
}

TEST(Median, RejectsBadArguments) {
  EXPECT_THROW(median(std::vector<double>{}), std::invalid_argument);
  EXPECT_THROW(median(std::vector<double>{1.0, nan, 2.0}), std::invalid_argument);
  EXPECT_THROW(median(std::vector<double>{1.0, inf}), std::invalid_argument);
}

// ||x - ref|| / ||ref||: (3, 4) against (0, 5) is ||(3, -1)|| / 5 = sqrt(10) / 5. Unequal lengths read past the end
// before; a zero reference gave 0 / 0.
TEST(RelativeDifference, HandComputedAndItsEdges) {
  EXPECT_DOUBLE_EQ(relative_difference(std::vector<double>{3.0, 4.0}, std::vector<double>{0.0, 5.0}),
                   std::sqrt(10.0) / 5.0);
  EXPECT_THROW(relative_difference(std::vector<double>{1.0}, std::vector<double>{1.0, 2.0}), std::invalid_argument);
  EXPECT_EQ(relative_difference(std::vector<double>{0.0, 0.0}, std::vector<double>{0.0, 0.0}), 0.0);
  EXPECT_EQ(relative_difference(std::vector<double>{0.0, 1e-3}, std::vector<double>{0.0, 0.0}), inf);
  EXPECT_TRUE(std::isnan(relative_difference(std::vector<double>{nan}, std::vector<double>{1.0})));
  EXPECT_TRUE(std::isnan(relative_difference(std::vector<double>{1.0}, std::vector<double>{nan})));
  EXPECT_TRUE(std::isnan(relative_difference(std::vector<double>{nan}, std::vector<double>{0.0})));
}

}  // namespace
}  // namespace lashid::sim::stats
