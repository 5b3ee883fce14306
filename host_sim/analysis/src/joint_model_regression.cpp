#include "joint_model_regression.hpp"

#include <algorithm>
#include <array>
#include <utility>

namespace lashid::sim::detail {

RegressionShape regression_shape(int n, int P, const FlatRecording& data, const ModelStructure& structure) {
  RegressionShape g;
  g.n = n;
  g.P = P;
  g.cols = n + n * P + 1 + (structure.drift ? 1 : 0);
  // A row and its n output lags all from the identification phases: val is never fitted to, also where a file puts
  // it before an identification phase (docs/data-format.md allows any order).
  std::size_t identification_run = 0;  // identification samples ending at t - 1
  for (std::size_t t = 0; t < data.size(); ++t) {
    if (data.is_identification(t) && identification_run >= static_cast<std::size_t>(n)) g.rows.push_back(t);
    identification_run = data.is_identification(t) ? identification_run + 1 : 0;
  }
  return g;
}

namespace {

// Least squares by lag sharing. The lag-i group of row t is the lag-1 group of row t - i + 1, so the sum over the
// rows of (lag i entries) x (lag i + d entries) is the sum over s = t - i of G(s) x G(s - d): over one run of
// consecutive rows [a, b), s runs over [a - i, b - i). Every lag shares the core [a - 1, b - n), summed once per
// d (into the block of lags 1 and 1 + d, then copied to the blocks (i, i + d)); each lag adds its own few samples
// at the run's two ends. This is n sums per pair of entries instead of n (n + 1) / 2 (the product columns' block
// of the finer tables at n = 3 is ~360 wide, and this is a diagnosis' most frequent computation).
NormalEquations least_squares_equations(const RegressionShape& g, const FlatRecording& data,
                                        const ModelStructure& structure, const std::vector<LagGroup>& groups) {
  const int n = g.n;
  const Eigen::Index P = g.P;
  NormalEquations ne;
  ne.zx = Eigen::MatrixXd::Zero(g.cols, g.cols);
  ne.zy = Eigen::VectorXd::Zero(g.cols);
  auto& zx = ne.zx;
  const Eigen::Index level = n + n * P;  // the offset kappa0's column; kappa1's follows it
  const double dtau = tau(1, data.size());  // tau(t) = t dtau
  const auto a_col = [](int lag) -> Eigen::Index { return lag - 1; };
  const auto p_col = [&](int lag, Eigen::Index point) { return n + (lag - 1) * P + point; };
  // The products of lag i's group at s and lag j's at s - (j - i), i <= j, into the upper triangle (a group with
  // itself: each unordered pair once; the a columns come before every product column, lag i's products before
  // lag j's).
  const auto add_products = [&](std::size_t s, int i, int j) {
    const LagGroup& x = groups[s];
    const LagGroup& z = groups[s - static_cast<std::size_t>(j - i)];
    zx(a_col(i), a_col(j)) += x.minus_y * z.minus_y;
    for (std::size_t k = 0; k < 2; ++k) {
      zx(a_col(i), p_col(j, z.point[k])) += x.minus_y * z.weight[k];
      if (i != j) zx(a_col(j), p_col(i, x.point[k])) += z.minus_y * x.weight[k];
    }
    if (i == j) {
      const Eigen::Index lo = std::min(x.point[0], x.point[1]), hi = std::max(x.point[0], x.point[1]);
      zx(p_col(i, x.point[0]), p_col(i, x.point[0])) += x.weight[0] * x.weight[0];
      zx(p_col(i, x.point[1]), p_col(i, x.point[1])) += x.weight[1] * x.weight[1];
      zx(p_col(i, lo), p_col(i, hi)) += x.weight[0] * x.weight[1];
    } else {
      for (std::size_t k = 0; k < 2; ++k) {
        for (std::size_t l = 0; l < 2; ++l) zx(p_col(i, x.point[k]), p_col(j, z.point[l])) += x.weight[k] * z.weight[l];
      }
    }
  };
  // Lag i's group at s times the level columns of row s + i (1 and tau(s + i)).
  const auto add_levels = [&](std::size_t s, int i) {
    const LagGroup& x = groups[s];
    const double tau_t = static_cast<double>(s + static_cast<std::size_t>(i)) * dtau;
    zx(a_col(i), level) += x.minus_y;
    for (std::size_t k = 0; k < 2; ++k) zx(p_col(i, x.point[k]), level) += x.weight[k];
    if (structure.drift) {
      zx(a_col(i), level + 1) += tau_t * x.minus_y;
      for (std::size_t k = 0; k < 2; ++k) zx(p_col(i, x.point[k]), level + 1) += tau_t * x.weight[k];
    }
  };
  std::vector<std::pair<std::size_t, std::size_t>> runs;
  for (std::size_t t : g.rows) {
    if (!runs.empty() && runs.back().second == t) {
      ++runs.back().second;
    } else {
      runs.emplace_back(t, t + 1);
    }
  }
  const auto un = static_cast<std::size_t>(n);
  const auto core = [&](std::pair<std::size_t, std::size_t> run) {
    const std::size_t lo = run.first - 1;
    return std::pair{lo, std::max(lo, run.second >= un ? run.second - un : 0)};
  };
  // 1. The cores, on the blocks of lag 1; the level columns' sums (sum G(s) and sum G(s) tau(s)) apart, as
  // (a, products) vectors.
  Eigen::VectorXd sum_one = Eigen::VectorXd::Zero(P + 1), sum_tau = Eigen::VectorXd::Zero(P + 1);
  for (const auto& run : runs) {
    const auto [lo, hi] = core(run);
    for (std::size_t s = lo; s < hi; ++s) {
      for (int d = 0; d < n; ++d) add_products(s, 1, 1 + d);
      const LagGroup& x = groups[s];
      const double tau_s = static_cast<double>(s) * dtau;
      sum_one(0) += x.minus_y;
      sum_tau(0) += tau_s * x.minus_y;
      for (std::size_t k = 0; k < 2; ++k) {
        sum_one(1 + x.point[k]) += x.weight[k];
        sum_tau(1 + x.point[k]) += tau_s * x.weight[k];
      }
    }
  }
  // 2. Copied to the blocks (i, i + d): a_i a_j, a_i x products_j, a_j x products_i, products_i x products_j.
  for (int d = 0; d < n; ++d) {
    for (int i = 2; i + d <= n; ++i) {
      const int j = i + d;
      zx(a_col(i), a_col(j)) = zx(a_col(1), a_col(1 + d));
      zx.block(a_col(i), p_col(j, 0), 1, P) = zx.block(a_col(1), p_col(1 + d, 0), 1, P);
      zx.block(a_col(j), p_col(i, 0), 1, P) = zx.block(a_col(1 + d), p_col(1, 0), 1, P);
      zx.block(p_col(i, 0), p_col(j, 0), P, P) = zx.block(p_col(1, 0), p_col(1 + d, 0), P, P);
    }
  }
  // 3. Each lag's ends of each run.
  for (const auto& run : runs) {
    const auto [lo, hi] = core(run);
    for (int i = 1; i <= n; ++i) {
      const auto ui = static_cast<std::size_t>(i);
      const std::size_t begin = run.first - ui, end = run.second - ui;
      for (const auto& [from, to] : {std::pair{begin, std::min(lo, end)}, std::pair{hi, end}}) {
        for (std::size_t s = from; s < to; ++s) {
          for (int j = i; j <= n; ++j) add_products(s, i, j);
          add_levels(s, i);
        }
      }
    }
  }
  // 4. The cores' level sums, for every lag: tau(s + i) = tau(s) + i dtau.
  for (int i = 1; i <= n; ++i) {
    const double shift = static_cast<double>(i) * dtau;
    zx(a_col(i), level) += sum_one(0);
    zx.block(p_col(i, 0), level, P, 1) += sum_one.tail(P);
    if (structure.drift) {
      zx(a_col(i), level + 1) += sum_tau(0) + shift * sum_one(0);
      zx.block(p_col(i, 0), level + 1, P, 1) += sum_tau.tail(P) + shift * sum_one.tail(P);
    }
  }
  // 5. What depends on the row itself: the targets and the level columns.
  for (std::size_t t : g.rows) {
    const double y = data.y[t], tau_t = static_cast<double>(t) * dtau;
    ne.yy += y * y;
    for (int i = 1; i <= n; ++i) {
      const LagGroup& x = groups[t - static_cast<std::size_t>(i)];
      ne.zy(a_col(i)) += x.minus_y * y;
      for (std::size_t k = 0; k < 2; ++k) ne.zy(p_col(i, x.point[k])) += x.weight[k] * y;
    }
    zx(level, level) += 1.0;
    ne.zy(level) += y;
    if (structure.drift) {
      zx(level, level + 1) += tau_t;
      zx(level + 1, level + 1) += tau_t * tau_t;
      ne.zy(level + 1) += tau_t * y;
    }
  }
  zx.triangularView<Eigen::StrictlyLower>() = zx.transpose();
  ne.energy = zx.diagonal();
  return ne;
}

}  // namespace

std::vector<LagGroup> lag_groups(const FlatRecording& data, const Basis& phi) {
  std::vector<LagGroup> groups(data.size());
  for (std::size_t s = 0; s < data.size(); ++s) {
    const HatRow& h = phi[s];
    const int first = h.param[0] >= 0 ? h.param[0] : std::max(h.param[1], 0);
    LagGroup& e = groups[s];
    e.minus_y = -data.y[s];
    for (std::size_t k = 0; k < 2; ++k) {
      e.point[k] = h.param[k] >= 0 ? h.param[k] : first;
      e.weight[k] = h.param[k] >= 0 ? h.weight[k] : 0.0;
    }
  }
  return groups;
}

std::vector<double> fitted_values(const RegressionShape& g, const FlatRecording& data, const ModelStructure& structure,
                                  const std::vector<LagGroup>& groups, const Eigen::VectorXd& theta) {
  const Eigen::Index level = g.n + g.n * static_cast<Eigen::Index>(g.P);
  std::vector<double> fitted;
  fitted.reserve(g.rows.size());
  for (std::size_t t : g.rows) {
    double sum = 0;
    for (int i = 1; i <= g.n; ++i) {
      const LagGroup& x = groups[t - static_cast<std::size_t>(i)];
      const Eigen::Index products = g.n + static_cast<Eigen::Index>(i - 1) * g.P;
      sum += x.minus_y * theta(i - 1);
      for (std::size_t k = 0; k < 2; ++k) sum += x.weight[k] * theta(products + x.point[k]);
    }
    sum += theta(level);
    if (structure.drift) sum += tau(t, data.size()) * theta(level + 1);
    fitted.push_back(sum);
  }
  return fitted;
}

NormalEquations normal_equations(const RegressionShape& g, const FlatRecording& data, const ModelStructure& structure,
                                 const Basis& phi, const std::vector<LagGroup>& groups,
                                 const std::vector<double>* instruments_y) {
  if (instruments_y == nullptr) return least_squares_equations(g, data, structure, groups);
  NormalEquations ne;
  ne.zx = Eigen::MatrixXd::Zero(g.cols, g.cols);
  ne.zy = Eigen::VectorXd::Zero(g.cols);
  ne.energy = Eigen::VectorXd::Zero(g.cols);
  // Instruments: the same row with the instruments' lags in the a_i columns (the first n entries of each lag group
  // are the y lags, in the same order in both visits).
  std::vector<std::vector<Entry>> z_rows;
  z_rows.reserve(g.rows.size());
  visit_rows(g, data, structure, phi, instruments_y,
             [&](std::size_t, const std::vector<Entry>& z, double) { z_rows.push_back(z); });
  std::size_t r = 0;
  visit_rows(g, data, structure, phi, nullptr, [&](std::size_t, const std::vector<Entry>& x, double y) {
    const std::vector<Entry>& z = z_rows[r++];
    for (const Entry& a : z) {
      ne.zy(a.column) += a.value * y;
      for (const Entry& b : x) ne.zx(a.column, b.column) += a.value * b.value;
    }
    for (const Entry& b : x) ne.energy(b.column) += b.value * b.value;
  });
  return ne;
}

}  // namespace lashid::sim::detail
