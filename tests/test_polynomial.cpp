// Roots, stability and reflection of monic polynomials (lashid/stats/polynomial.hpp), against closed forms.
#include "lashid/stats/polynomial.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

namespace {

using lashid::sim::stats::is_stable;
using lashid::sim::stats::polynomial_from_roots;
using lashid::sim::stats::polynomial_roots;
using lashid::sim::stats::reflected_into_unit_circle;

// |A(e^jw)| for A(z) = z^n + a_1 z^(n-1) + ... + a_n.
double magnitude(const std::vector<double>& a, double w) {
  const std::complex<double> z = std::polar(1.0, w);
  std::complex<double> value = 1.0;
  for (double c : a) value = value * z + c;
  return std::abs(value);
}

TEST(Polynomial, RootsOfAProductOfKnownFactors) {
  // (z - 0.5)(z - 2) = z^2 - 2.5 z + 1.
  std::vector<std::complex<double>> roots = polynomial_roots({-2.5, 1.0});
  ASSERT_EQ(roots.size(), 2U);
  std::sort(roots.begin(), roots.end(), [](auto x, auto y) { return x.real() < y.real(); });
  EXPECT_NEAR(roots[0].real(), 0.5, 1e-12);
  EXPECT_NEAR(roots[1].real(), 2.0, 1e-12);
  EXPECT_NEAR(std::abs(roots[0].imag()) + std::abs(roots[1].imag()), 0.0, 1e-12);
  EXPECT_TRUE(polynomial_roots({}).empty());
}

TEST(Polynomial, FromRootsMultipliesTheFactorsOut) {
  // (z - 0.6)^2 = z^2 - 1.2 z + 0.36; r e^(+-j pi/3): z^2 - 2 r cos(pi/3) z + r^2.
  const std::vector<double> a = polynomial_from_roots({0.6, 0.6});
  ASSERT_EQ(a.size(), 2U);
  EXPECT_NEAR(a[0], -1.2, 1e-12);
  EXPECT_NEAR(a[1], 0.36, 1e-12);
  const double r = 0.9;
  const std::vector<double> pair =
      polynomial_from_roots({std::polar(r, std::numbers::pi / 3), std::polar(r, -std::numbers::pi / 3)});
  EXPECT_NEAR(pair[0], -r, 1e-12);
  EXPECT_NEAR(pair[1], r * r, 1e-12);
}

TEST(Polynomial, StableOnlyWithEveryRootStrictlyInsideTheUnitCircle) {
  EXPECT_TRUE(is_stable({-1.2, 0.36}));
  EXPECT_FALSE(is_stable({-2.5, 1.0}));  // a root at 2
  EXPECT_FALSE(is_stable({-1.0}));       // a root at 1, on the circle
  EXPECT_FALSE(is_stable({-1.25, 1.5625}));  // 1.25 e^(+-j pi/3)
  EXPECT_TRUE(is_stable({}));
}

TEST(Polynomial, ReflectionMovesUnstableRootsToTheirInverseAndScalesTheMagnitudeResponse) {
  // (z - 0.5)(z - 2) -> (z - 0.5)^2 = z^2 - z + 0.25; |e^jw - 1/2| = |e^jw - 2| / 2 at every w.
  const std::vector<double> real_roots = reflected_into_unit_circle({-2.5, 1.0});
  ASSERT_EQ(real_roots.size(), 2U);
  EXPECT_NEAR(real_roots[0], -1.0, 1e-12);
  EXPECT_NEAR(real_roots[1], 0.25, 1e-12);
  // 1.25 e^(+-j pi/3) -> 0.8 e^(+-j pi/3): z^2 - 0.8 z + 0.64; the magnitude scaled by 1 / 1.25^2.
  const std::vector<double> unstable{-1.25, 1.5625};
  const std::vector<double> pair = reflected_into_unit_circle(unstable);
  EXPECT_NEAR(pair[0], -0.8, 1e-12);
  EXPECT_NEAR(pair[1], 0.64, 1e-12);
  for (double w : {0.0, 0.3, 1.0, 2.0, std::numbers::pi}) {
    EXPECT_NEAR(magnitude(real_roots, w), magnitude({-2.5, 1.0}, w) / 2.0, 1e-12) << "w = " << w;
    EXPECT_NEAR(magnitude(pair, w), magnitude(unstable, w) / (1.25 * 1.25), 1e-12) << "w = " << w;
  }
  // A stable polynomial comes back unchanged.
  EXPECT_EQ(reflected_into_unit_circle({-1.2, 0.36}), (std::vector<double>{-1.2, 0.36}));
}

}  // namespace
