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
  // Only the upper triangle is summed into (the lower one is its copy, made at the end): only it is zeroed.
  ne.zx.resize(g.cols, g.cols);
  ne.zx.triangularView<Eigen::Upper>().setZero();
  ne.zy = Eigen::VectorXd::Zero(g.cols);
  auto& zx = ne.zx;
  const Eigen::Index level = n + n * P;  // the offset kappa0's column; kappa1's follows it
  const double dtau = tau(1, data.size());  // tau(t) = t dtau
  const auto a_col = [](int lag) -> Eigen::Index { return lag - 1; };
  const auto p_col = [&](int lag, Eigen::Index point) { return n + (lag - 1) * P + point; };
  // The products of lag i's group at s and lag j's at s - (j - i), i <= j, into the upper triangle (a group with
  // itself: each unordered pair once; the a columns come before every product column, lag i's products before
  // lag j's). On the matrix's storage, the groups' entries read into locals first: through zx(., .) every store
  // made the compiler load the groups again (a double may alias them), and this is most of the equations' time.
  double* const m = zx.data();
  const Eigen::Index ld = zx.outerStride();
  const auto column = [m, ld](Eigen::Index c) { return m + c * ld; };
  const auto add_products = [&](std::size_t s, int i, int j) {
    const LagGroup& x = groups[s];
    const LagGroup& z = groups[s - static_cast<std::size_t>(j - i)];
    const double xm = x.minus_y, xw0 = x.weight[0], xw1 = x.weight[1];
    const double zm = z.minus_y, zw0 = z.weight[0], zw1 = z.weight[1];
    const Eigen::Index ai = a_col(i), aj = a_col(j);
    const Eigen::Index x0 = p_col(i, x.point[0]), x1 = p_col(i, x.point[1]);  // lag i's product rows
    double* const z0 = column(p_col(j, z.point[0]));                          // lag j's product columns
    double* const z1 = column(p_col(j, z.point[1]));
    column(aj)[ai] += xm * zm;
    if (i == j) {
      z0[ai] += xm * zw0;
      z1[ai] += xm * zw1;
      column(x0)[x0] += xw0 * xw0;
      column(x1)[x1] += xw1 * xw1;
      column(std::max(x0, x1))[std::min(x0, x1)] += xw0 * xw1;
    } else {
      z0[ai] += xm * zw0;
      column(x0)[aj] += zm * xw0;
      z1[ai] += xm * zw1;
      column(x1)[aj] += zm * xw1;
      z0[x0] += xw0 * zw0;
      z1[x0] += xw0 * zw1;
      z0[x1] += xw1 * zw0;
      z1[x1] += xw1 * zw1;
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
  double* const one = sum_one.data();
  double* const one_tau = sum_tau.data();
  for (const auto& run : runs) {
    const auto [lo, hi] = core(run);
    for (std::size_t s = lo; s < hi; ++s) {
      for (int d = 0; d < n; ++d) add_products(s, 1, 1 + d);
      const LagGroup& x = groups[s];
      const double xm = x.minus_y, xw0 = x.weight[0], xw1 = x.weight[1];  // locals, as in add_products
      const Eigen::Index p0 = 1 + x.point[0], p1 = 1 + x.point[1];
      const double tau_s = static_cast<double>(s) * dtau;
      one[0] += xm;
      one_tau[0] += tau_s * xm;
      one[p0] += xw0;
      one_tau[p0] += tau_s * xw0;
      one[p1] += xw1;
      one_tau[p1] += tau_s * xw1;
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
  double* const zy = ne.zy.data();  // as in add_products, the groups' entries (and the sum of y^2) in locals
  double yy = 0;
  for (std::size_t t : g.rows) {
    const double y = data.y[t], tau_t = static_cast<double>(t) * dtau;
    yy += y * y;
    for (int i = 1; i <= n; ++i) {
      const LagGroup& x = groups[t - static_cast<std::size_t>(i)];
      const double xm = x.minus_y, xw0 = x.weight[0], xw1 = x.weight[1];
      const Eigen::Index xc0 = p_col(i, x.point[0]), xc1 = p_col(i, x.point[1]);
      zy[a_col(i)] += xm * y;
      zy[xc0] += xw0 * y;
      zy[xc1] += xw1 * y;
    }
    zx(level, level) += 1.0;
    ne.zy(level) += y;
    if (structure.drift) {
      zx(level, level + 1) += tau_t;
      zx(level + 1, level + 1) += tau_t * tau_t;
      ne.zy(level + 1) += tau_t * y;
    }
  }
  ne.yy = yy;
  // The lower triangle from the upper one, tile by tile: column by column, the transposed reads would take a
  // cache line each.
  constexpr Eigen::Index kTile = 32;
  const Eigen::Index cols = g.cols;
  for (Eigen::Index c0 = 0; c0 < cols; c0 += kTile) {
    for (Eigen::Index r0 = c0; r0 < cols; r0 += kTile) {
      const Eigen::Index c1 = std::min(c0 + kTile, cols), r1 = std::min(r0 + kTile, cols);
      for (Eigen::Index c = c0; c < c1; ++c) {
        for (Eigen::Index r = std::max(r0, c + 1); r < r1; ++r) m[r + c * ld] = m[c + r * ld];
      }
    }
  }
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
  const double* const th = theta.data();
  std::vector<double> fitted(g.rows.size());
  for (std::size_t r = 0; r < g.rows.size(); ++r) {
    const std::size_t t = g.rows[r];
    double sum = 0;
    for (int i = 1; i <= g.n; ++i) {
      const LagGroup& x = groups[t - static_cast<std::size_t>(i)];
      const double* const products = th + g.n + static_cast<Eigen::Index>(i - 1) * g.P;
      sum += x.minus_y * th[i - 1];
      sum += x.weight[0] * products[x.point[0]];
      sum += x.weight[1] * products[x.point[1]];
    }
    sum += th[level];
    if (structure.drift) sum += tau(t, data.size()) * th[level + 1];
    fitted[r] = sum;
  }
  return fitted;
}

void row_entries(const RegressionShape& g, const FlatRecording& data, const ModelStructure& structure,
                 const Basis& phi, const std::vector<double>& y_lags, std::size_t t, std::vector<Entry>& entries) {
  entries.clear();
  for (int i = 1; i <= g.n; ++i) {
    const std::size_t lag = t - static_cast<std::size_t>(i);
    entries.push_back({i - 1, -y_lags[lag]});
    const HatRow& h = phi[lag];
    for (std::size_t k = 0; k < 2; ++k) {
      if (h.param[k] >= 0) entries.push_back({g.n + (i - 1) * g.P + h.param[k], h.weight[k]});
    }
  }
  entries.push_back({g.n + g.n * g.P, 1.0});
  if (structure.drift) entries.push_back({g.n + g.n * g.P + 1, tau(t, data.size())});
}

NormalEquations normal_equations(const RegressionShape& g, const FlatRecording& data, const ModelStructure& structure,
                                 const Basis& phi, const std::vector<LagGroup>& groups,
                                 const std::vector<double>* instruments_y) {
  if (instruments_y == nullptr) return least_squares_equations(g, data, structure, groups);
  NormalEquations ne;
  ne.zx = Eigen::MatrixXd::Zero(g.cols, g.cols);
  ne.zy = Eigen::VectorXd::Zero(g.cols);
  ne.energy = Eigen::VectorXd::Zero(g.cols);
  // Instruments: the same row with the instruments' lags in the a_i columns. Within a row every (instrument,
  // regressor) pair is a different entry of Z'X, so each entry's sum runs over the rows in order whatever the order
  // of the pairs; the two rows are built in reused buffers (a copy of every instrument row was a third of this).
  std::vector<Entry> x, z;
  double* const zy = ne.zy.data();
  double* const energy = ne.energy.data();
  double* const m = ne.zx.data();
  const Eigen::Index ld = ne.zx.outerStride();
  for (std::size_t t : g.rows) {
    row_entries(g, data, structure, phi, *instruments_y, t, z);
    row_entries(g, data, structure, phi, data.y, t, x);
    const double y = data.y[t];
    for (const Entry& a : z) {
      const Eigen::Index row = a.column;
      const double value = a.value;
      zy[row] += value * y;
      for (const Entry& b : x) m[row + b.column * ld] += value * b.value;
    }
    for (const Entry& b : x) energy[b.column] += b.value * b.value;
  }
  return ne;
}

}  // namespace lashid::sim::detail
