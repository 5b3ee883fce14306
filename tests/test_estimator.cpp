// The estimation against the paper and closed forms: exact recovery on noise-free data (3.20), grouped RLS == batch
// LS (3.21) in double and float32, the cross-check, bad input as a status, heap-freedom. The building blocks (schedule,
// validation, Lagrange basis, eigenvalues, step mean): test_estimator_design.cpp.
// Eigen's malloc guard reports through eigen_assert, which NDEBUG turns off, and every build CI runs defines NDEBUG
// (Release, and the sanitizer presets): defined here, before any Eigen header, so that the guard holds in every
// build; a negative control below shows that it does.
#include <cstdio>
#include <cstdlib>
#define eigen_assert(x)                                       \
  do {                                                        \
    if (!(x)) {                                               \
      std::fputs("eigen_assert failed: " #x "\n", stderr);   \
      std::abort();                                           \
    }                                                         \
  } while (false)
#define EIGEN_RUNTIME_NO_MALLOC
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <random>
#include <vector>

#include "lashid/estimator/batch_ls.hpp"
#include "lashid/estimator/covariance_rls.hpp"
#include "lashid/estimator/cross_check.hpp"
#include "lashid/estimator/excitation.hpp"
#include "lashid/estimator/identifier.hpp"
#include "paper_examples.hpp"

namespace {

using namespace lashid::est;
using lashid::test::AisExample;
using lashid::test::DisExample;

// Heap use inside the estimator fails the test (Eigen asserts when it would allocate).
struct NoMalloc {
  NoMalloc() { Eigen::internal::set_is_malloc_allowed(false); }
  ~NoMalloc() { Eigen::internal::set_is_malloc_allowed(true); }
};

// The negative control: a dynamic Eigen matrix under the guard must abort, in this build (Release or not).
TEST(NoMallocGuard, StopsAHeapAllocationInEveryBuild) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_DEATH(
      {
        const NoMalloc guard;
        Eigen::MatrixXd m(3, 3);
        m.setZero();
      },
      "heap allocation is forbidden");
}

struct Experiment {
  ExperimentDesign<double, 6> design;
  std::vector<double> step_v, step_y, pulse_v, pulse_y;
};

template <class Border>
Experiment generate_dpe(Scheme scheme, double v_min, double v_max, const std::array<double, 6>& V,
                        std::array<double, 2> a, std::array<double, 2> b, Border F, double noise_sd, int L, int N,
                        unsigned seed) {
  Experiment x;
  x.design.scheme = scheme;
  x.design.v_min = v_min;
  x.design.v_max = v_max;
  for (int j = 0; j < 6; ++j) x.design.V(j) = V[static_cast<std::size_t>(j)];
  const ExcitationGenerator<double, 2, 6> gen(x.design);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> xi(0.0, noise_sd);
  // Start at the equilibrium of the held output, so that noise-free the step mean is exactly B(1)u/A(1).
  const double held_u = F(x.design.held_level());
  const double y_eq = (b[0] + b[1]) * held_u / (1 + a[0] + a[1]);
  double y1 = y_eq, y2 = y_eq, u1 = held_u, u2 = held_u;
  auto plant = [&](double u) {  // y(t) = -a1 y(t-1) - a2 y(t-2) + b1 u(t-1) + b2 u(t-2) + xi(t)
    const double y = -a[0] * y1 - a[1] * y2 + b[0] * u1 + b[1] * u2 + (noise_sd > 0 ? xi(rng) : 0.0);
    y2 = y1;
    y1 = y;
    u2 = u1;
    u1 = u;
    return y;
  };
  for (int t = 0; t <= L; ++t) {
    x.step_v.push_back(gen.step_input(t));
    x.step_y.push_back(plant(held_u));  // from t = 1 on the operator sits at the held output (3.4)-(3.5)
  }
  for (int t = 0; t < N; ++t) {
    x.pulse_v.push_back(gen.pulse_input(t));
    x.pulse_y.push_back(plant(F(x.pulse_v.back())));
  }
  return x;
}

template <class Scalar, template <class, int, int> class Solver = GroupedLeastSquares>
SchemeIdentifier<Scalar, 2, 6, Solver> feed(const Experiment& x, int* failed_updates = nullptr) {
  ExperimentDesign<Scalar, 6> d;
  d.scheme = x.design.scheme;
  d.v_min = static_cast<Scalar>(x.design.v_min);
  d.v_max = static_cast<Scalar>(x.design.v_max);
  d.V = x.design.V.cast<Scalar>();
  SchemeIdentifier<Scalar, 2, 6, Solver> id;
  EXPECT_EQ(id.configure(d), Status::kOk);
  const NoMalloc guard;
  for (std::size_t t = 0; t < x.step_v.size(); ++t) {
    EXPECT_EQ(id.add_step_sample(static_cast<Scalar>(x.step_v[t]), static_cast<Scalar>(x.step_y[t])), Status::kOk);
  }
  for (std::size_t t = 0; t < x.pulse_v.size(); ++t) {
    const Status s = id.add_pulse_sample(static_cast<Scalar>(x.pulse_v[t]), static_cast<Scalar>(x.pulse_y[t]));
    if (s == Status::kOk) continue;
    if (failed_updates != nullptr) {
      ++*failed_updates;
    } else {
      ADD_FAILURE() << "t=" << t << ": " << to_string(s);
    }
  }
  return id;
}

Experiment dis_experiment(double noise_sd, int L, int N, unsigned seed) {
  return generate_dpe(Scheme::kDescending, DisExample::v_min, DisExample::v_max, DisExample::V, DisExample::a,
                      DisExample::b, DisExample::F_d, noise_sd, L, N, seed);
}
Experiment ais_experiment(double noise_sd, int L, int N, unsigned seed) {
  return generate_dpe(Scheme::kAscending, AisExample::v_min, AisExample::v_max, AisExample::V, AisExample::a(),
                      AisExample::b(), AisExample::F_a, noise_sd, L, N, seed);
}

TEST(Recovery, DisNoiseFreeIsExact) {
  const NoMalloc guard;
  const auto e = feed<double>(dis_experiment(0.0, 50, 400, 1)).estimate();
  ASSERT_EQ(e.status, Status::kOk) << to_string(e.status);
  const double u_M = DisExample::u_M();
  EXPECT_NEAR(e.ybar0, (70.5 - 35.25) * u_M / 2.21, 1e-12);  // (3.7)
  EXPECT_NEAR(e.a(0), 1.0, 1e-9);
  EXPECT_NEAR(e.a(1), 0.21, 1e-9);
  EXPECT_NEAR(e.b(0), 70.5, 1e-9);
  EXPECT_NEAR(e.b(1), -35.25, 1e-9);
  EXPECT_NEAR(e.held_output, u_M, 1e-9);
  for (int j = 0; j < 6; ++j) {
    const double V = DisExample::V[static_cast<std::size_t>(j)];
    const double W = V - DisExample::v_max;
    EXPECT_NEAR(e.c(j), (DisExample::F_d(V) - u_M) / W, 1e-9) << "c_" << j + 1;  // (3.14b)
    EXPECT_NEAR(e.F(j), DisExample::F_d(V), 1e-9) << "F^d(V_" << j + 1 << ")";  // Table 2, exact values
    // mu_ij = b_i c_j (3.18)
    for (int i = 0; i < 2; ++i) {
      EXPECT_NEAR(e.ls.theta(2 + 2 * j + i), DisExample::b[static_cast<std::size_t>(i)] * e.c(j), 1e-8);
    }
  }
  EXPECT_NEAR(e.F(0), DisExample::u_m(), 1e-9);  // V_1^d = v_m
}

TEST(Recovery, AisNoiseFreeIsExact) {
  const NoMalloc guard;
  const auto e = feed<double>(ais_experiment(0.0, 50, 400, 1)).estimate();
  ASSERT_EQ(e.status, Status::kOk) << to_string(e.status);
  EXPECT_NEAR(e.a(0), -1.25, 1e-9);
  EXPECT_NEAR(e.a(1), 0.375, 1e-9);
  EXPECT_NEAR(e.b(0), 4 * AisExample::K(), 1e-9);  // 11.4105 (4.6)
  EXPECT_NEAR(e.b(1), -AisExample::K(), 1e-9);     // -2.8526
  EXPECT_NEAR(e.held_output, AisExample::u_m(), 1e-9);
  for (int j = 0; j < 6; ++j) {
    const double V = AisExample::V[static_cast<std::size_t>(j)];
    EXPECT_NEAR(e.F(j), AisExample::F_a(V), 1e-9) << "F^a(V_" << j + 1 << ")";  // Table 5, exact values
  }
  EXPECT_NEAR(e.F(0), AisExample::u_M(), 1e-9);  // V_1^a = v_M
}

TEST(GroupedLeastSquares, EqualsBatchLeastSquaresOnNoisyData) {
  for (unsigned seed : {1u, 2u, 3u}) {
    const Experiment x = dis_experiment(4.0, 2000, 2000, seed);
    const auto g = feed<double>(x).estimate();
    const auto b = feed<double, BatchLeastSquares>(x).estimate();
    ASSERT_EQ(g.status, Status::kOk);
    ASSERT_EQ(b.status, Status::kOk);
    EXPECT_EQ(g.ls.rows, b.ls.rows);
    EXPECT_LT((g.ls.theta - b.ls.theta).norm() / b.ls.theta.norm(), 1e-10) << "seed " << seed;
    EXPECT_NEAR(g.ls.noise_variance, b.ls.noise_variance, 1e-8 * b.ls.noise_variance);
    EXPECT_LT((g.ls.std_error - b.ls.std_error).cwiseAbs().maxCoeff(), 1e-6 * b.ls.std_error.maxCoeff());
  }
}

// float32 recursive vs double batch (3.21), relative difference of Theta. Target of the issue: <= 1e-3, aim 1e-4.
double float_vs_double(const Experiment& x, double* rcond = nullptr) {
  const auto f = feed<float>(x).estimate();
  const auto d = feed<double, BatchLeastSquares>(x).estimate();
  EXPECT_EQ(f.status, Status::kOk) << to_string(f.status);
  EXPECT_EQ(d.status, Status::kOk) << to_string(d.status);
  if (rcond != nullptr) *rcond = static_cast<double>(f.ls.rcond);
  return (f.ls.theta.cast<double>() - d.ls.theta).norm() / d.ls.theta.norm();
}

TEST(GroupedLeastSquares, Float32MatchesDoubleBatchOnThePaperExamples) {
  double rcond = 0;
  const double dis = float_vs_double(dis_experiment(4.0, 2000, 2000, 11), &rcond);
  RecordProperty("dis_rel_diff", std::to_string(dis));
  std::printf("DIS N=2000: float32 grouped vs double batch: %.3g (reduced rcond %.3g)\n", dis, rcond);
  EXPECT_LT(dis, 1e-4);
  const double ais = float_vs_double(ais_experiment(std::sqrt(0.15), 2000, 8000, 12), &rcond);
  std::printf("AIS N=8000: float32 grouped vs double batch: %.3g (reduced rcond %.3g)\n", ais, rcond);
  EXPECT_LT(ais, 1e-4);
}

TEST(GroupedLeastSquares, Float32StaysBoundedOverAMillionSamples) {
  const double dis = float_vs_double(dis_experiment(4.0, 2000, 1'000'000, 21));
  std::printf("DIS N=1e6: float32 grouped vs double batch: %.3g\n", dis);
  EXPECT_LT(dis, 1e-4);
  const double ais = float_vs_double(ais_experiment(std::sqrt(0.15), 2000, 1'000'000, 22));
  std::printf("AIS N=1e6: float32 grouped vs double batch: %.3g\n", ais);
  EXPECT_LT(ais, 1e-4);
}

TEST(CovarianceRls, Float32DriftsWhereTheGroupedFormDoesNot) {
  // The textbook baseline, for the record (docs/estimator.md): same data, float32 covariance form.
  // It either reports a loss of positive definiteness (1 + phi'P phi <= 0) or ends far from (3.21).
  const Experiment x = dis_experiment(4.0, 2000, 200'000, 31);
  int breakdowns = 0;
  const auto c = feed<float, CovarianceRls>(x, &breakdowns).estimate();
  const auto d = feed<double, BatchLeastSquares>(x).estimate();
  const double rel = (c.ls.theta.cast<double>() - d.ls.theta).norm() / d.ls.theta.norm();
  const double grouped = float_vs_double(x);
  std::printf("DIS N=2e5: float32 covariance RLS vs double batch: %.3g, %d rejected updates (grouped: %.3g)\n", rel,
              breakdowns, grouped);
  EXPECT_TRUE(breakdowns > 0 || rel > 10 * grouped);
}

TEST(CrossCheck, LargestZOverAAndBInCombinedStandardErrors) {
  // se(b_i) = |W_1| se(mu_i1), |W_1| = v_M - v_m.
  EXPECT_DOUBLE_EQ(b_std_error(0.5, -3.0, 4.0), 3.5);
  const std::vector<double> a_d{1.0, 0.2}, a_a{1.0, 0.5}, se_a{0.1, 0.1};
  const std::vector<double> b_d{70.0, -35.0}, b_a{66.0, -35.5}, se_b{1.0, 1.0};
  const CrossCheck<double> c = cross_check(LinearEstimate<double>{a_d, se_a, b_d, se_b},
                                           LinearEstimate<double>{a_a, se_a, b_a, se_b});
  EXPECT_EQ(c.status, Status::kOk);
  EXPECT_NEAR(c.max_z, 4.0 / std::sqrt(2.0), 1e-12);  // b_1 beats a_2's 0.3 / sqrt(0.02) = 2.12
  EXPECT_EQ(c.worst, 2);                              // index n + 0: b_1
  const std::vector<double> one{1.0};
  const CrossCheck<double> bad = cross_check(LinearEstimate<double>{a_d, se_a, b_d, se_b},
                                             LinearEstimate<double>{one, se_a, b_a, se_b});
  EXPECT_EQ(bad.status, Status::kOrderOutOfRange);
}

// One y too large for the float32 sums (3e19: its square overflows) but finite: refused like a NaN, with the same
// estimate as the run where that sample is a NaN. Before, it was taken, and every later estimate was ill-conditioned.
TEST(SchemeIdentifier, ASampleTooLargeForTheSumsIsRefusedLikeANaN) {
  const Experiment x = dis_experiment(4.0, 2000, 6000, 3);
  Experiment huge = x;
  Experiment nan = x;
  huge.pulse_y[3000] = 3e19;
  nan.pulse_y[3000] = std::nan("");
  int refused_huge = 0;
  int refused_nan = 0;
  const auto with_huge = feed<float>(huge, &refused_huge).estimate();
  const auto with_nan = feed<float>(nan, &refused_nan).estimate();
  ASSERT_EQ(with_huge.status, Status::kOk);
  EXPECT_GT(refused_huge, 0);
  EXPECT_EQ(refused_huge, refused_nan);
  EXPECT_TRUE((with_huge.ls.theta.array() == with_nan.ls.theta.array()).all());
  // The step experiment refuses it too (the mean would hold it).
  SchemeIdentifier<float, 2, 6> id;
  ExperimentDesign<float, 6> d;
  d.v_min = -3;
  d.v_max = 4;
  d.V << -3, -2, -1, 1, 2, 3;
  ASSERT_EQ(id.configure(d), Status::kOk);
  ASSERT_EQ(id.add_step_sample(-3.0f, 1.0f), Status::kOk);
  EXPECT_EQ(id.add_step_sample(4.0f, 3e19f), Status::kNonFinite);
  EXPECT_EQ(id.add_step_sample(4.0f, -1e15f), Status::kNonFinite);
  EXPECT_EQ(id.add_step_sample(4.0f, 1e13f), Status::kOk);
}

TEST(SchemeIdentifier, ReportsBadInputAsStatus) {
  SchemeIdentifier<float, 2, 6> id;
  EXPECT_EQ(id.add_step_sample(4.0f, 1.0f), Status::kNotConfigured);
  ExperimentDesign<float, 6> d;
  d.v_min = -3;
  d.v_max = 4;
  d.V << -3, -2, -1, 1, 2, 3;
  ASSERT_EQ(id.configure(d), Status::kOk);
  EXPECT_EQ(id.add_pulse_sample(4.0f, 1.0f), Status::kStepMeanMissing);
  EXPECT_EQ(id.add_step_sample(4.0f, 1.0f), Status::kInputOffDesign);  // t = 0 must be v_m
  EXPECT_EQ(id.add_step_sample(4.0f, 1.0f), Status::kOk);
  EXPECT_EQ(id.add_step_sample(4.0f, std::nanf("")), Status::kNonFinite);
  EXPECT_EQ(id.add_pulse_sample(0.5f, 1.0f), Status::kInputOffDesign);  // not a design abscissa
  EXPECT_EQ(id.estimate().status, Status::kNotExcited);
  // A failed configure() leaves nothing usable, the step mean included.
  ExperimentDesign<float, 6> bad = d;
  bad.v_max = -4;
  EXPECT_EQ(id.configure(bad), Status::kIntervalInvalid);
  EXPECT_EQ(id.add_pulse_sample(4.0f, 1.0f), Status::kNotConfigured);
  EXPECT_EQ(id.add_step_sample(-3.0f, 1.0f), Status::kNotConfigured);
}

}  // namespace
