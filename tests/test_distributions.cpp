// Distribution functions of the statistics layer against closed forms, published table values and reference values
// of an arbitrary-precision library.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "lashid/stats/metrics.hpp"
#include "lashid/stats/statistics.hpp"
#include "statistics_support.hpp"

namespace lashid::sim::stats {
namespace {

using test::inf;
using test::nan;
using test::relatively_near;

// ---------------------------------------------------------------------------------------------------------

TEST(NormalCdf, TableValuesAndSymmetry) {
  EXPECT_TRUE(relatively_near(normal_cdf(-1.0), 0.15865525393145707, 1e-14));
  EXPECT_TRUE(relatively_near(normal_cdf(1.0), 1.0 - 0.15865525393145707, 1e-15));
  EXPECT_EQ(normal_cdf(0.0), 0.5);
  EXPECT_NEAR(normal_cdf(1.959963984540054), 0.975, 1e-15);
  EXPECT_TRUE(relatively_near(normal_cdf(-10.0), 7.619853024160527e-24, 1e-12));  // lower tail keeps accuracy
  EXPECT_EQ(normal_cdf(-inf), 0.0);
  EXPECT_EQ(normal_cdf(inf), 1.0);
  EXPECT_THROW(normal_cdf(nan), std::invalid_argument);
}

TEST(NormalQuantile, TableValues) {
  EXPECT_TRUE(relatively_near(normal_quantile(0.975), 1.959963984540054, 1e-14));
  EXPECT_TRUE(relatively_near(normal_quantile(0.025), -1.959963984540054, 1e-14));
  EXPECT_TRUE(relatively_near(normal_quantile(0.995), 2.5758293035489, 1e-13));
  EXPECT_TRUE(relatively_near(normal_quantile(0.9), 1.2815515655446004, 1e-14));
  EXPECT_TRUE(relatively_near(normal_quantile(0.999), 3.090232306167813, 1e-13));
  EXPECT_EQ(normal_quantile(0.5), 0.0);
}

TEST(NormalQuantile, InvertsTheCdfDeepInTheTails) {
  for (const double p : {1e-300, 1e-100, 1e-20, 1e-8, 1e-3, 0.01, 0.3, 0.49999}) {
    const double z = normal_quantile(p);
    // Conditioning: a relative error d in z changes Phi(z) by about z^2 d relatively (|z| = 37 at 1e-300).
    EXPECT_TRUE(relatively_near(normal_cdf(z), p, 1e-14 * std::max(1.0, z * z))) << "p = " << p;
    // The upper tail, where 1 - p is representable: Phi(-q) = 1 - Phi(q) = p for q = Phi^-1(1 - p) (the symmetry
    // of the normal law, checked through normal_cdf, not through the quantile's own mirror). 1 - p carries an
    // absolute rounding of up to 1.1e-16, a relative 1.1e-16 / p in the tail probability.
    if (p >= 1e-8) {
      const double q = normal_quantile(1.0 - p);
      EXPECT_GT(q, 0.0) << "p = " << p;
      EXPECT_TRUE(relatively_near(normal_cdf(-q), p, 1e-14 * std::max(1.0, q * q) + 2.3e-16 / p)) << "p = " << p;
    }
  }
}

TEST(NormalQuantile, RejectsProbabilitiesOutsideTheOpenUnitInterval) {
  for (const double p : {0.0, 1.0, -0.1, 1.5, nan}) EXPECT_THROW(normal_quantile(p), std::invalid_argument) << p;
}

// ---------------------------------------------------------------------------------------------------------

TEST(RegularizedGammaQ, ClosedFormsForAOneAndOneHalf) {
  for (const double x : {0.0, 1e-6, 0.3, 1.0, 2.5, 7.0, 40.0, 300.0}) {
    EXPECT_TRUE(relatively_near(regularized_gamma_q(1.0, x), std::exp(-x), 1e-13)) << "x = " << x;
    EXPECT_TRUE(relatively_near(regularized_gamma_q(0.5, x), std::erfc(std::sqrt(x)), 1e-13)) << "x = " << x;
  }
  EXPECT_EQ(regularized_gamma_q(3.0, inf), 0.0);
}

TEST(RegularizedGammaQ, RejectsBadArguments) {
  EXPECT_THROW(regularized_gamma_q(0.0, 1.0), std::invalid_argument);
  EXPECT_THROW(regularized_gamma_q(-1.0, 1.0), std::invalid_argument);
  EXPECT_THROW(regularized_gamma_q(1.0, -1.0), std::invalid_argument);
  EXPECT_THROW(regularized_gamma_q(nan, 1.0), std::invalid_argument);
  EXPECT_THROW(regularized_gamma_q(1.0, nan), std::invalid_argument);
}

TEST(Chi2Sf, TwoDegreesOfFreedomIsExponential) {
  for (const double x : {0.01, 0.5, 1.0, 3.0, 10.0, 100.0, 1000.0}) {
    EXPECT_TRUE(relatively_near(chi2_sf(x, 2.0), std::exp(-x / 2.0), 1e-13)) << "x = " << x;
  }
}

TEST(Chi2Sf, OneDegreeOfFreedomIsTheNormalTail) {
  // P(Z^2 > x) = erfc(sqrt(x / 2)).
  for (const double x : {1e-4, 0.2, 1.0, 3.0, 9.0, 50.0}) {
    EXPECT_TRUE(relatively_near(chi2_sf(x, 1.0), std::erfc(std::sqrt(x / 2.0)), 1e-13)) << "x = " << x;
  }
}

TEST(Chi2Sf, EvenDegreesOfFreedomMatchThePoissonSum) {
  // For dof = 2k: P(X > x) = e^{-x/2} sum_{j<k} (x/2)^j / j! (A&S 26.4.21), summed here in log space.
  for (const int k : {2, 5, 25, 100}) {
    for (const double factor : {0.2, 0.7, 0.95, 1.0, 1.1, 1.5, 3.0}) {
      const double y = factor * k;
      double expected = 0.0;
      for (int j = 0; j < k; ++j) {
        expected += std::exp(-y + j * std::log(y) - std::lgamma(j + 1.0));
      }
      EXPECT_TRUE(relatively_near(chi2_sf(2.0 * y, 2.0 * k), expected, 1e-11)) << "dof " << 2 * k << ", x " << 2 * y;
    }
  }
}

TEST(Chi2Sf, ManyDegreesOfFreedom) {
  // Gamma(dof / 2) overflows a double beyond dof ~ 340; the tails must still come out. Reference values:
  // mpmath 1.3 gammainc(dof / 2, x / 2, inf, regularized=True) at 40 digits.
  EXPECT_TRUE(relatively_near(chi2_sf(2e5, 2e5), 0.49957947788963482331, 1e-12));
  EXPECT_TRUE(relatively_near(chi2_sf(2.02e5, 2e5), 0.00080842151292559073247, 1e-12));
  EXPECT_TRUE(relatively_near(chi2_sf(1.98e5, 2e5), 0.99924258007882523203, 1e-12));
  EXPECT_TRUE(relatively_near(chi2_sf(2.2e5, 2e5), 2.6554004793766944689e-206, 1e-10));
  EXPECT_EQ(chi2_sf(1e-10, 2e5), 1.0);
  EXPECT_EQ(regularized_gamma_q(1e5, 0.0), 1.0);
  EXPECT_EQ(chi2_sf(1e300, 3.0), 0.0);  // underflows to 0, no error
}

TEST(Chi2Sf, PublishedCriticalValues) {
  EXPECT_TRUE(relatively_near(chi2_sf(3.841458820694124, 1.0), 0.05, 1e-12));
  EXPECT_TRUE(relatively_near(chi2_sf(18.307038053275146, 10.0), 0.05, 1e-12));
  EXPECT_TRUE(relatively_near(chi2_sf(6.634896601021214, 1.0), 0.01, 1e-12));
}

TEST(Chi2Sf, EdgesAndBadArguments) {
  EXPECT_EQ(chi2_sf(0.0, 3.0), 1.0);
  EXPECT_EQ(chi2_sf(-1.0, 3.0), 1.0);
  EXPECT_EQ(chi2_sf(inf, 3.0), 0.0);
  EXPECT_THROW(chi2_sf(1.0, 0.0), std::invalid_argument);
  EXPECT_THROW(chi2_sf(1.0, -2.0), std::invalid_argument);
  EXPECT_THROW(chi2_sf(1.0, inf), std::invalid_argument);
  EXPECT_THROW(chi2_sf(nan, 2.0), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------------------------

TEST(RegularizedBeta, ClosedForms) {
  for (const double x : {0.0, 0.01, 0.2, 0.5, 0.77, 0.99, 1.0}) {
    for (const double a : {0.5, 1.0, 3.0, 20.0}) {
      // I_x(a, 1) = x^a, I_x(1, b) = 1 - (1 - x)^b.
      EXPECT_NEAR(regularized_beta(a, 1.0, x), std::pow(x, a), 1e-14) << "a " << a << ", x " << x;
      EXPECT_NEAR(regularized_beta(1.0, a, x), 1.0 - std::pow(1.0 - x, a), 1e-14) << "b " << a << ", x " << x;
      EXPECT_NEAR(regularized_beta(a, a, 0.5), 0.5, 1e-14) << "a " << a;
    }
  }
  // Relative accuracy in the far lower tail: I_x(a, 1) = x^a.
  EXPECT_TRUE(relatively_near(regularized_beta(30.0, 1.0, 0.01), 1e-60, 1e-12));
}

TEST(RegularizedBeta, Symmetry) {
  for (const double x : {0.05, 0.3, 0.6, 0.95}) {
    EXPECT_NEAR(regularized_beta(2.5, 7.0, x), 1.0 - regularized_beta(7.0, 2.5, 1.0 - x), 1e-14) << x;
  }
}

TEST(RegularizedBeta, RejectsBadArguments) {
  EXPECT_THROW(regularized_beta(0.0, 1.0, 0.5), std::invalid_argument);
  EXPECT_THROW(regularized_beta(1.0, -1.0, 0.5), std::invalid_argument);
  EXPECT_THROW(regularized_beta(1.0, 1.0, -0.1), std::invalid_argument);
  EXPECT_THROW(regularized_beta(1.0, 1.0, 1.1), std::invalid_argument);
  EXPECT_THROW(regularized_beta(1.0, 1.0, nan), std::invalid_argument);
}

TEST(StudentT, ClosedFormsForOneAndTwoDegreesOfFreedom) {
  for (const double t : {0.0, 0.1, 1.0, -2.5, 12.706204736174707, 1e3, -1e8}) {
    // Cauchy: P(|T| > t) = 1 - 2 atan(|t|) / pi. Two dof: 1 - |t| / sqrt(2 + t^2).
    const double cauchy = 1.0 - 2.0 * std::atan(std::fabs(t)) / std::numbers::pi;
    const double two = 1.0 - std::fabs(t) / std::sqrt(2.0 + t * t);
    EXPECT_NEAR(student_t_two_sided_p(t, 1.0), cauchy, 1e-14) << t;
    EXPECT_NEAR(student_t_two_sided_p(t, 2.0), two, 1e-14) << t;
  }
  EXPECT_TRUE(relatively_near(student_t_two_sided_p(12.706204736174707, 1.0), 0.05, 1e-12));
  // Far tail keeps relative accuracy: 2 dof, p = 1 - t / sqrt(2 + t^2) ~ 1 / t^2 for large t.
  EXPECT_TRUE(relatively_near(student_t_two_sided_p(1e6, 2.0), 1.0 / (1e12 + 0.5), 1e-9));
}

TEST(StudentT, OneDegreeOfFreedomNearZeroKeepsTheCauchyClosedForm) {
  // P(|T| > t) = 1 - 2 atan(t) / pi, and F(1, 1) is T^2 (Boost 1.74 alone is off by up to 1e-10 here, see
  // statistics.cpp).
  for (const double t : {1e-300, 1e-10, 1e-8, 1e-4, 0.3, 0.7, 0.9}) {
    const double cauchy = 1.0 - 2.0 * std::atan(t) / std::numbers::pi;
    EXPECT_TRUE(relatively_near(student_t_two_sided_p(t, 1.0), cauchy, 1e-15)) << t;
    EXPECT_TRUE(relatively_near(f_sf(t * t, 1.0, 1.0), cauchy, 1e-15)) << t;
  }
}

TEST(StudentT, PublishedCriticalValue) {
  EXPECT_TRUE(relatively_near(student_t_two_sided_p(2.228138851986, 10.0), 0.05, 1e-11));
  EXPECT_TRUE(relatively_near(student_t_two_sided_p(-2.228138851986, 10.0), 0.05, 1e-11));
  EXPECT_EQ(student_t_two_sided_p(0.0, 10.0), 1.0);
  EXPECT_EQ(student_t_two_sided_p(inf, 10.0), 0.0);
  EXPECT_THROW(student_t_two_sided_p(1.0, 0.0), std::invalid_argument);
  EXPECT_THROW(student_t_two_sided_p(nan, 3.0), std::invalid_argument);
}

TEST(FisherF, PublishedCriticalValue) {
  EXPECT_TRUE(relatively_near(f_sf(4.964602743730711, 1.0, 10.0), 0.05, 1e-12));
}

TEST(FisherF, ClosedFormsForTwoDegreesOfFreedom) {
  for (const double d : {1.0, 3.0, 10.0, 55.0}) {
    for (const double f : {0.01, 0.5, 1.0, 4.0, 30.0, 1e4}) {
      // d1 = 2: P(F > f) = (1 + 2 f / d2)^{-d2/2}. d2 = 2: 1 - (d1 f / (2 + d1 f))^{d1/2}.
      EXPECT_TRUE(relatively_near(f_sf(f, 2.0, d), std::pow(1.0 + 2.0 * f / d, -d / 2.0), 1e-12)) << d << " " << f;
      EXPECT_NEAR(f_sf(f, d, 2.0), 1.0 - std::pow(d * f / (2.0 + d * f), d / 2.0), 1e-14) << d << " " << f;
    }
  }
  EXPECT_TRUE(relatively_near(f_sf(1e6, 2.0, 10.0), std::pow(1.0 + 2e5, -5.0), 1e-11));  // ~3e-27
}

TEST(FisherF, OneNumeratorDegreeIsTheSquaredT) {
  for (const double d : {1.0, 4.0, 10.0, 120.0}) {
    for (const double f : {0.05, 1.0, 3.3, 25.0, 400.0}) {
      EXPECT_TRUE(relatively_near(f_sf(f, 1.0, d), student_t_two_sided_p(std::sqrt(f), d), 1e-13)) << d << " " << f;
    }
  }
}

TEST(FisherF, EdgesAndBadArguments) {
  EXPECT_EQ(f_sf(0.0, 3.0, 4.0), 1.0);
  EXPECT_EQ(f_sf(-2.0, 3.0, 4.0), 1.0);
  EXPECT_EQ(f_sf(inf, 3.0, 4.0), 0.0);
  EXPECT_THROW(f_sf(1.0, 0.0, 4.0), std::invalid_argument);
  EXPECT_THROW(f_sf(1.0, 3.0, -4.0), std::invalid_argument);
  EXPECT_THROW(f_sf(nan, 3.0, 4.0), std::invalid_argument);
}

}  // namespace
}  // namespace lashid::sim::stats
