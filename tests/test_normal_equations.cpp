// The joint model's normal equations (host_sim/analysis/src/joint_model_regression.cpp) against a second
// implementation: the dense regression matrix of (3.19), written here from its definition, and X'X, X'y, y'y by
// Eigen. The library sums products of lag groups once per lag difference and copies them between lags (only the
// ends of each run of identification rows differ), which a wrong run boundary, copy or drift term would break.
#include <cstddef>
#include <random>
#include <vector>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "joint_model_regression.hpp"

namespace {

using namespace lashid::sim;
using lashid::sim::detail::Basis;
using lashid::sim::detail::HatRow;

struct Case {
  FlatRecording data;
  Basis phi;
};

// Identification rows in runs of several lengths (one shorter than any lag, one of a single sample), separated
// by val samples, which the regression leaves out.
Case make_case(int P, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  std::uniform_int_distribution<int> param(-1, P - 1);
  Case c;
  const std::vector<std::pair<int, Phase>> pieces{{40, Phase::kStepD}, {3, Phase::kVal},  {1, Phase::kDis},
                                                  {2, Phase::kVal},      {2, Phase::kStepA}, {5, Phase::kVal},
                                                  {57, Phase::kAis}, {9, Phase::kVal},   {31, Phase::kDis}};
  for (const auto& [count, phase] : pieces) {
    for (int k = 0; k < count; ++k) {
      c.data.v.push_back(value(rng));
      c.data.y.push_back(value(rng));
      c.data.phase.push_back(phase);
      HatRow h;
      h.param = {param(rng), param(rng)};
      if (h.param[0] == h.param[1]) h.param[1] = -1;  // a row's two hat weights are on distinct points
      h.weight = {value(rng), value(rng)};
      c.phi.push_back(h);
    }
  }
  return c;
}

// The dense regression (3.19): row t has -y_lags(t - i) in a_i's column, phi(t - i)'s hat weights in the columns
// of b_i c_p, 1 for kappa0 and t / (N - 1) for kappa1.
Eigen::MatrixXd dense_regression(const Case& c, const detail::RegressionShape& g, bool drift,
                                 const std::vector<double>& y_lags) {
  const int n = g.n, P = g.P;
  const std::size_t N = c.data.size();
  Eigen::MatrixXd X = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(g.rows.size()), g.cols);
  for (std::size_t r = 0; r < g.rows.size(); ++r) {
    const std::size_t t = g.rows[r];
    const auto row = static_cast<Eigen::Index>(r);
    for (int i = 1; i <= n; ++i) {
      const std::size_t s = t - static_cast<std::size_t>(i);
      X(row, i - 1) = -y_lags[s];
      for (std::size_t k = 0; k < 2; ++k) {
        if (c.phi[s].param[k] >= 0) X(row, n + (i - 1) * P + c.phi[s].param[k]) += c.phi[s].weight[k];
      }
    }
    X(row, n + n * P) = 1.0;
    if (drift) X(row, n + n * P + 1) = static_cast<double>(t) / static_cast<double>(N - 1);
  }
  return X;
}

Eigen::VectorXd targets(const Case& c, const detail::RegressionShape& g) {
  Eigen::VectorXd y(static_cast<Eigen::Index>(g.rows.size()));
  for (std::size_t r = 0; r < g.rows.size(); ++r) y(static_cast<Eigen::Index>(r)) = c.data.y[g.rows[r]];
  return y;
}

TEST(NormalEquations, EqualTheDenseRegressionsProducts) {
  const int P = 7;
  for (int n = 1; n <= 4; ++n) {
    for (bool drift : {false, true}) {
      const Case c = make_case(P, static_cast<unsigned>(10 * n + (drift ? 1 : 0)));
      ModelStructure structure;
      structure.drift = drift;
      const detail::RegressionShape g = detail::regression_shape(n, P, c.data, structure);
      const Eigen::MatrixXd X = dense_regression(c, g, drift, c.data.y);
      const Eigen::VectorXd y = targets(c, g);
      const std::vector<detail::LagGroup> groups = detail::lag_groups(c.data, c.phi);
      const detail::NormalEquations ne = detail::normal_equations(g, c.data, structure, c.phi, groups, nullptr);
      const Eigen::MatrixXd xx = X.transpose() * X;
      EXPECT_LT((ne.zx - xx).cwiseAbs().maxCoeff(), 1e-12 * xx.cwiseAbs().maxCoeff())
          << "n " << n << " drift " << drift;
      EXPECT_LT((ne.zy - X.transpose() * y).cwiseAbs().maxCoeff(), 1e-12 * xx.cwiseAbs().maxCoeff())
          << "n " << n << " drift " << drift;
      EXPECT_NEAR(ne.yy, y.squaredNorm(), 1e-12 * y.squaredNorm());
      EXPECT_LT((ne.energy - xx.diagonal()).cwiseAbs().maxCoeff(), 1e-12 * xx.cwiseAbs().maxCoeff());
      // Instrumental variables with y itself as the instruments: the same equations.
      const detail::NormalEquations iv = detail::normal_equations(g, c.data, structure, c.phi, groups, &c.data.y);
      EXPECT_LT((iv.zx - xx).cwiseAbs().maxCoeff(), 1e-12 * xx.cwiseAbs().maxCoeff()) << "n " << n;
    }
  }
}

// Instruments other than y (as the IV fit's simulated outputs): Z'X is not symmetric, Z'y takes Z's rows, and the
// columns' energies stay those of X.
TEST(NormalEquations, InstrumentalVariablesEqualTheDenseProducts) {
  const int P = 7;
  for (int n = 1; n <= 4; ++n) {
    for (bool drift : {false, true}) {
      const Case c = make_case(P, static_cast<unsigned>(100 + 10 * n + (drift ? 1 : 0)));
      std::mt19937 rng(static_cast<unsigned>(n));
      std::normal_distribution<double> noise(0.0, 0.3);
      std::vector<double> instruments = c.data.y;
      for (double& value : instruments) value = 0.5 * value + noise(rng);
      ModelStructure structure;
      structure.drift = drift;
      const detail::RegressionShape g = detail::regression_shape(n, P, c.data, structure);
      const Eigen::MatrixXd X = dense_regression(c, g, drift, c.data.y);
      const Eigen::MatrixXd Z = dense_regression(c, g, drift, instruments);
      const Eigen::VectorXd y = targets(c, g);
      const std::vector<detail::LagGroup> groups = detail::lag_groups(c.data, c.phi);
      const detail::NormalEquations iv = detail::normal_equations(g, c.data, structure, c.phi, groups, &instruments);
      const Eigen::MatrixXd zx = Z.transpose() * X;
      const double scale = zx.cwiseAbs().maxCoeff();
      ASSERT_GT((zx - zx.transpose()).cwiseAbs().maxCoeff(), 1e-3 * scale);  // the instruments differ from y
      EXPECT_LT((iv.zx - zx).cwiseAbs().maxCoeff(), 1e-12 * scale) << "n " << n << " drift " << drift;
      EXPECT_LT((iv.zy - Z.transpose() * y).cwiseAbs().maxCoeff(), 1e-12 * scale) << "n " << n << " drift " << drift;
      EXPECT_LT((iv.energy - X.colwise().squaredNorm().transpose()).cwiseAbs().maxCoeff(), 1e-12 * scale);
    }
  }
}

}  // namespace
