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
  for (std::size_t t = static_cast<std::size_t>(n); t < data.size(); ++t) {
    if (data.is_identification(t)) g.rows.push_back(t);
  }
  return g;
}

namespace {

// The entries of one lag group of a row: -y(s) in the a column, then the hat weights of phi(s) (slot = border
// parameter, or -1 for the a column).
struct LagGroup {
  int count = 0;
  std::array<int, 3> slot{};
  std::array<double, 3> value{};
};

LagGroup lag_group(const FlatRecording& data, const Basis& phi, std::size_t s) {
  LagGroup e;
  e.slot[0] = -1;
  e.value[0] = -data.y[s];
  e.count = 1;
  const HatRow& h = phi[s];
  for (std::size_t k = 0; k < 2; ++k) {
    if (h.param[k] >= 0) {
      e.slot[static_cast<std::size_t>(e.count)] = h.param[k];
      e.value[static_cast<std::size_t>(e.count++)] = h.weight[k];
    }
  }
  return e;
}

// Least squares by lag sharing. The lag-i group of row t is the lag-1 group of row t - i + 1, so the sum over the
// rows of (lag i entries) x (lag i + d entries) is the sum over s = t - i of G(s) x G(s - d): over one run of
// consecutive rows [a, b), s runs over [a - i, b - i). Every lag shares the core [a - 1, b - n), summed once per
// d (into the block of lags 1 and 1 + d, then copied to the blocks (i, i + d)); each lag adds its own few samples
// at the run's two ends. This is n sums per pair of entries instead of n (n + 1) / 2, and half of the fit's
// normal equations' time (the product columns' block of the finer tables at n = 3 is ~300 wide).
NormalEquations least_squares_equations(const RegressionShape& g, const FlatRecording& data,
                                        const ModelStructure& structure, const Basis& phi) {
  const int n = g.n, P = g.P;
  NormalEquations ne;
  ne.zx = Eigen::MatrixXd::Zero(g.cols, g.cols);
  ne.zy = Eigen::VectorXd::Zero(g.cols);
  const Eigen::Index level = n + n * P;  // the offset kappa0's column; kappa1's follows it
  const double dtau = tau(1, data.size());  // tau(t) = t dtau
  const auto column = [&](int slot, int lag) -> Eigen::Index {
    return slot < 0 ? lag - 1 : n + static_cast<Eigen::Index>(lag - 1) * P + slot;
  };
  // Lag i's group at s times lag j's at s - (j - i), i <= j, into the upper triangle (each unordered pair of a
  // group with itself once).
  const auto add_products = [&](const LagGroup& x, int i, const LagGroup& y, int j) {
    for (int p = 0; p < x.count; ++p) {
      const Eigen::Index cx = column(x.slot[static_cast<std::size_t>(p)], i);
      const double vx = x.value[static_cast<std::size_t>(p)];
      for (int q = i == j ? p : 0; q < y.count; ++q) {
        const Eigen::Index cy = column(y.slot[static_cast<std::size_t>(q)], j);
        ne.zx(std::min(cx, cy), std::max(cx, cy)) += vx * y.value[static_cast<std::size_t>(q)];
      }
    }
  };
  // Lag i's group at s times the level columns of row s + i.
  const auto add_levels = [&](const LagGroup& x, int i, double one, double tau_t) {
    for (int p = 0; p < x.count; ++p) {
      const Eigen::Index cx = column(x.slot[static_cast<std::size_t>(p)], i);
      ne.zx(cx, level) += one * x.value[static_cast<std::size_t>(p)];
      if (structure.drift) ne.zx(cx, level + 1) += tau_t * x.value[static_cast<std::size_t>(p)];
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
  // 1. The cores, on the blocks of lag 1; the level columns' sums (sum G(s) and sum G(s) tau(s)) apart.
  Eigen::VectorXd sum_one = Eigen::VectorXd::Zero(P + 1), sum_tau = Eigen::VectorXd::Zero(P + 1);  // slot + 1
  for (const auto& run : runs) {
    const auto [lo, hi] = core(run);
    for (std::size_t s = lo; s < hi; ++s) {
      const LagGroup x = lag_group(data, phi, s);
      for (int d = 0; d < n; ++d) add_products(x, 1, lag_group(data, phi, s - static_cast<std::size_t>(d)), 1 + d);
      for (int p = 0; p < x.count; ++p) {
        const auto k = static_cast<Eigen::Index>(x.slot[static_cast<std::size_t>(p)] + 1);
        sum_one(k) += x.value[static_cast<std::size_t>(p)];
        sum_tau(k) += x.value[static_cast<std::size_t>(p)] * tau(s, data.size());
      }
    }
  }
  // 2. Copied to the blocks (i, i + d): a_i a_j, a_i x products_j, a_j x products_i, products_i x products_j.
  for (int d = 0; d < n; ++d) {
    const int j1 = 1 + d;
    for (int i = 2; i + d <= n; ++i) {
      const int j = i + d;
      ne.zx(i - 1, j - 1) = ne.zx(0, j1 - 1);
      ne.zx.block(i - 1, column(0, j), 1, P) = ne.zx.block(0, column(0, j1), 1, P);
      ne.zx.block(j - 1, column(0, i), 1, P) = ne.zx.block(j1 - 1, column(0, 1), 1, P);
      ne.zx.block(column(0, i), column(0, j), P, P) = ne.zx.block(column(0, 1), column(0, j1), P, P);
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
          const LagGroup x = lag_group(data, phi, s);
          for (int j = i; j <= n; ++j) add_products(x, i, lag_group(data, phi, s - static_cast<std::size_t>(j - i)), j);
          add_levels(x, i, 1.0, tau(s + ui, data.size()));
        }
      }
    }
  }
  // 4. The cores' level sums, for every lag: tau(s + i) = tau(s) + i dtau.
  for (int i = 1; i <= n; ++i) {
    for (Eigen::Index k = 0; k <= P; ++k) {
      const Eigen::Index c = column(static_cast<int>(k) - 1, i);
      ne.zx(c, level) += sum_one(k);
      if (structure.drift) ne.zx(c, level + 1) += sum_tau(k) + static_cast<double>(i) * dtau * sum_one(k);
    }
  }
  // 5. What depends on the row itself: the targets and the level columns.
  for (std::size_t t : g.rows) {
    const double y = data.y[t], tt = tau(t, data.size());
    ne.yy += y * y;
    for (int i = 1; i <= n; ++i) {
      const LagGroup x = lag_group(data, phi, t - static_cast<std::size_t>(i));
      for (int p = 0; p < x.count; ++p) ne.zy(column(x.slot[static_cast<std::size_t>(p)], i)) += x.value[static_cast<std::size_t>(p)] * y;
    }
    ne.zx(level, level) += 1.0;
    ne.zy(level) += y;
    if (structure.drift) {
      ne.zx(level, level + 1) += tt;
      ne.zx(level + 1, level + 1) += tt * tt;
      ne.zy(level + 1) += tt * y;
    }
  }
  ne.zx.triangularView<Eigen::StrictlyLower>() = ne.zx.transpose();
  ne.energy = ne.zx.diagonal();
  return ne;
}

}  // namespace

NormalEquations normal_equations(const RegressionShape& g, const FlatRecording& data, const ModelStructure& structure,
                                 const Basis& phi, const std::vector<double>* instruments_y) {
  if (instruments_y == nullptr) return least_squares_equations(g, data, structure, phi);
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
