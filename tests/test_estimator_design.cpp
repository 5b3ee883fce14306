// The estimator's building blocks against the paper and closed forms: the pulse schedule (Theorem 3.1), the design's
// validation (3.1)/(4.2) and the classifier's resolution, the Lagrange basis (3.15), the eigenvalues of the condition
// checks, the step mean (3.7). The estimation itself: test_estimator.cpp.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include <cmath>
#include <random>

#include "lashid/estimator/design.hpp"
#include "lashid/estimator/identifier.hpp"
#include "lashid/estimator/lagrange.hpp"
#include "lashid/estimator/step_mean.hpp"
#include "lashid/estimator/symmetric_eigenvalues.hpp"

namespace {

using namespace lashid::est;

TEST(PulseSchedule, MatchesTheorem31) {
  using S = PulseSchedule<2, 6>;  // T = n(m+3) = 18, tau_1 = 2n = 4, tau_j = (2+j)n
  EXPECT_EQ(S::kPeriod, 18);
  const int expected[] = {4, 8, 10, 12, 14, 16};
  for (int j = 1; j <= 6; ++j) EXPECT_EQ(S::tau(j), expected[j - 1]) << "j=" << j;
  using S3 = PulseSchedule<3, 4>;  // T = 21, tau = 6, 12, 15, 18
  EXPECT_EQ(S3::kPeriod, 21);
  EXPECT_EQ(S3::tau(1), 6);
  EXPECT_EQ(S3::tau(2), 12);
  EXPECT_EQ(S3::tau(4), 18);
  // Over two periods, pulse j sits exactly at t_k + tau_j and nowhere else.
  int pulses = 0;
  for (int t = 0; t < 2 * 18; ++t) {
    const int j = S::pulse_at(t);
    if (j != 0) {
      ++pulses;
      EXPECT_EQ(t % 18, expected[j - 1]);
    }
  }
  EXPECT_EQ(pulses, 12);
}

TEST(PulseSchedule, OrderOneKeepsTheReturnToTheHeldLevel) {
  // (3.25) with n = 1 would put pulses 1 sample apart, against (3.1)'s tau_j - tau_{j-1} >= 2.
  using S = PulseSchedule<1, 4>;
  for (int j = 2; j <= 4; ++j) EXPECT_GE(S::tau(j) - S::tau(j - 1), 2);
}

TEST(ExperimentDesign, RejectsWhatThePaperForbids) {
  ExperimentDesign<double, 3> d;
  d.scheme = Scheme::kDescending;
  d.v_min = -3;
  d.v_max = 4;
  d.V << -3, -1, 2;
  EXPECT_EQ(d.validate(), Status::kOk);
  d.V << -2, -1, 2;  // V_1^d must equal v_m
  EXPECT_EQ(d.validate(), Status::kAbscissasNotOrdered);
  d.V << -3, 2, -1;  // not increasing
  EXPECT_EQ(d.validate(), Status::kAbscissasNotOrdered);
  d.V << -3, -1, 4;  // V_m^d must be < v_M
  EXPECT_EQ(d.validate(), Status::kAbscissasNotOrdered);
  d.V << -3, -1, std::nan("");
  EXPECT_EQ(d.validate(), Status::kAbscissasNotOrdered);
  d.V << -3, -1, 2;
  d.v_max = -3;
  EXPECT_EQ(d.validate(), Status::kIntervalInvalid);
  d.v_max = 4;
  d.scheme = Scheme::kAscending;  // AIS: v_M = V_1^a > ... > V_m^a > v_m
  EXPECT_EQ(d.validate(), Status::kAbscissasNotOrdered);
  d.V << 4, 1, -2;
  EXPECT_EQ(d.validate(), Status::kOk);
  d.V << 4, 1, -3;
  EXPECT_EQ(d.validate(), Status::kAbscissasNotOrdered);
  EXPECT_EQ(check_orders(0, 6, 3, 8), Status::kOrderOutOfRange);
  EXPECT_EQ(check_orders(2, 9, 3, 8), Status::kOrderOutOfRange);
  EXPECT_EQ(check_orders(2, 6, 3, 8), Status::kOk);
}

// Strictly ordered levels that float32's classifier cannot tell apart (its tolerance is 64 eps of the largest |W_j|,
// here 7 x 64 x 1.19e-7 = 5.3e-5): before, the design validated, every sample classified, and the estimate stayed
// "not excited" forever. The same levels in double are resolved.
TEST(ExperimentDesign, RefusesLevelsTheClassifierCannotTellApart) {
  ExperimentDesign<float, 6> f;
  f.v_min = -3;
  f.v_max = 4;
  f.V << -3, -2, -1, 1, 2, 3;
  EXPECT_EQ(f.validate(), Status::kOk);
  f.V << -3, -2, -1, 1, 2, 2.00003f;  // 3e-5 from its neighbour
  EXPECT_EQ(f.validate(), Status::kAbscissasTooClose);
  f.V << -3, -2, -1, 1, 2, 3.99997f;  // 3e-5 from the held level v_M = 4
  EXPECT_EQ(f.validate(), Status::kAbscissasTooClose);
  SchemeIdentifier<float, 2, 6> id;
  EXPECT_EQ(id.configure(f), Status::kAbscissasTooClose);
  ExperimentDesign<double, 6> d;
  d.v_min = -3;
  d.v_max = 4;
  d.V << -3, -2, -1, 1, 2, 2.00003;
  EXPECT_EQ(d.validate(), Status::kOk);
}

TEST(LagrangeBasis, KroneckerPropertyAndPartitionOfUnity) {
  Eigen::Matrix<double, 6, 1> W;
  W << -7, -6, -5, -3, -2, -1;  // W_j = V_j^d - v_M of the DIS example
  const LagrangeBasis<double, 6> basis(W);
  for (int j = 0; j < 6; ++j) {
    for (int i = 0; i < 6; ++i) EXPECT_NEAR(basis.P(j, W(i)), i == j ? 1.0 : 0.0, 1e-12) << i << "," << j;
  }
  // Lagrange polynomials of degree m-1 reproduce constants and w itself: sum P_j = 1, sum W_j P_j(w) = w.
  for (double w : {0.0, -4.0, 0.5, -6.5}) {
    double sum = 0, lin = 0;
    for (int j = 0; j < 6; ++j) {
      sum += basis.P(j, w);
      lin += W(j) * basis.P(j, w);
    }
    EXPECT_NEAR(sum, 1.0, 1e-12);
    EXPECT_NEAR(lin, w, 1e-11);
  }
  EXPECT_EQ(basis.classify(0.0), (LagrangeBasis<double, 6>::kZero));
  EXPECT_EQ(basis.classify(-5.0), 2);
  EXPECT_EQ(basis.classify(-4.0), (LagrangeBasis<double, 6>::kOffDesign));
}

TEST(SymmetricEigenvalues, MatchClosedFormAndEigensSolver) {
  Eigen::Matrix2d A;
  A << 2, 1, 1, 2;  // eigenvalues 1 and 3
  const Eigen::Vector2d ev = symmetric_eigenvalues<double, 2>(A);
  EXPECT_NEAR(ev(0), 1.0, 1e-15);
  EXPECT_NEAR(ev(1), 3.0, 1e-15);
  // Q diag(lambda) Q' with a random orthogonal Q and eigenvalues spread over 8 decades (cond 1e8).
  std::mt19937_64 rng(5);
  std::normal_distribution<double> g;
  Eigen::Matrix<double, 14, 14> X;
  for (int i = 0; i < 14; ++i) {
    for (int j = 0; j < 14; ++j) X(i, j) = g(rng);
  }
  const Eigen::Matrix<double, 14, 14> Q = X.householderQr().householderQ();
  Eigen::Matrix<double, 14, 1> lambda;
  for (int k = 0; k < 14; ++k) lambda(k) = std::pow(10.0, -8.0 + 8.0 * k / 13.0);
  const Eigen::Matrix<double, 14, 14> S = Q * lambda.asDiagonal() * Q.transpose();
  const auto jacobi = symmetric_eigenvalues<double, 14>(S);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 14, 14>> reference(S, Eigen::EigenvaluesOnly);
  for (int k = 0; k < 14; ++k) {
    EXPECT_NEAR(jacobi(k), lambda(k), 1e-14) << k;  // absolute accuracy ~ eps ||S||
    EXPECT_NEAR(jacobi(k), reference.eigenvalues()(k), 1e-14) << k;
  }
  EXPECT_NEAR((reciprocal_condition_spd<double, 14>(S)), 1e-8, 1e-13);
  Eigen::Matrix2d singular;
  singular << 1, 1, 1, 1;
  EXPECT_NEAR((reciprocal_condition_spd<double, 2>(singular)), 0.0, 1e-15);
  singular(0, 0) = std::nan("");
  EXPECT_EQ((reciprocal_condition_spd<double, 2>(singular)), 0.0);
}

TEST(StepMean, SkipsTheFirstSampleAndIsExactForAConstant) {
  StepMean<float> mean;
  EXPECT_FALSE(mean.ready());
  EXPECT_EQ(mean.add(0, 1000.0f), Status::kOk);  // t = 0: input still at the opposite bound
  for (int t = 1; t <= 100000; ++t) EXPECT_EQ(mean.add(t, 26.37f + ((t % 2) != 0 ? 0.5f : -0.5f)), Status::kOk);
  EXPECT_NEAR(mean.mean(), 26.37f, 2e-5f);
  EXPECT_NEAR(mean.variance(), 0.25f, 1e-4f);
  EXPECT_EQ(mean.add(7, std::nanf("")), Status::kNonFinite);
}

}  // namespace
