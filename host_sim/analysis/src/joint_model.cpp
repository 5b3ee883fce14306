#include "lashid/analysis/joint_model.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <future>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>

#include <Eigen/Dense>
#include <fmt/format.h>

#include "lashid/plant/border.hpp"
#include "lashid/plant/operators.hpp"
#include "joint_model_consistency.hpp"
#include "joint_model_layout.hpp"
#include "joint_model_regression.hpp"
#include "joint_model_output_error.hpp"
#include "joint_model_regime_search.hpp"
#include "joint_model_solve.hpp"
#include "model_operator.hpp"

namespace lashid::sim {

using detail::Basis;
using detail::BorderLayout;
using detail::Entry;
using detail::HatRow;
using detail::Layout;
using detail::make_layout;
using detail::normal_equations;
using detail::NormalEquations;
using detail::operator_basis;
using detail::refine_rank_one;
using detail::regression_shape;
using detail::RegressionShape;
using detail::solve_normal_equations;
using detail::SmoothnessStencil;
using detail::tau;

namespace {

// Border points the operator never moves through in these experiments (e.g. a backlash behind an input lag
// that holds through a pulse) have all-zero columns: they are left out of the regression and filled by
// interpolation afterwards (their value does not affect this data, only the simulation elsewhere). With the
// smoothness prior (ModelStructure::border_smoothness > 0, the default) no point is left out: the prior determines
// every point the data do not reach.
struct ExcitedColumns {
  std::vector<bool> excited;        ///< per border parameter p
  std::vector<Eigen::Index> keep;   ///< the regression columns kept
};

ExcitedColumns excited_columns(const Eigen::VectorXd& energy, int n, int P, int cols, bool smoothed) {
  ExcitedColumns e;
  e.excited.assign(static_cast<std::size_t>(P), false);
  // With the smoothness prior, every point is determined: by the data or the prior.
  if (smoothed) e.excited.assign(static_cast<std::size_t>(P), true);
  const auto is_basis = [&](Eigen::Index k) { return k >= n && k < n + n * P; };
  for (Eigen::Index k = 0; k < cols; ++k) {
    if (is_basis(k) && energy(k) > 0) e.excited[static_cast<std::size_t>((k - n) % P)] = true;
  }
  for (Eigen::Index k = 0; k < cols; ++k) {
    if (!is_basis(k) || e.excited[static_cast<std::size_t>((k - n) % P)]) e.keep.push_back(k);
  }
  return e;
}

// A border point whose hat weights, squared and summed over the identification rows, stay below this (a handful
// of samples' worth) is left to the smoothness prior: estimated from the data alone, such a point takes whatever
// value the noise gives it, and a simulation that goes there (val's reversals, a backlash behind an input lag)
// follows it (a backlash behind an input lag of exactly the plant's lambda reaches some points for a sample or
// two: its val simulation swung between -20 % and 96 % before this).
constexpr double kDeterminedEnergy = 5.0;

// The smoothness prior as extra rows (zero targets), added to the normal equations: per point between the
// abscissas and per b_i, sqrt(weight) (b_i c_centre - interpolation of b_i c_left, b_i c_right). `weight` counts in
// samples: a point reached by many samples follows the data, one reached by few stays near the line through its
// neighbours. The instruments of these rows are the rows themselves.
void add_smoothness_prior(const Layout& layout, int n, int P, double weight, NormalEquations& ne) {
  if (layout.stencils.empty() || !(weight > 0)) return;
  for (const SmoothnessStencil& st : layout.stencils) {
    if (st.centre < layout.level_parameters && ne.energy(n + st.centre) >= kDeterminedEnergy) continue;
    for (int i = 0; i < n; ++i) {
      std::vector<Entry> row{{n + i * P + st.centre, 1.0}};
      if (st.left >= 0) row.push_back({n + i * P + st.left, -st.left_weight});
      if (st.right >= 0) row.push_back({n + i * P + st.right, -st.right_weight});
      for (const Entry& a : row) {
        for (const Entry& b : row) ne.zx(a.column, b.column) += weight * a.value * b.value;
      }
    }
  }
}

// The border values at the layout's abscissas from the factor c; unexcited points by linear interpolation between
// the nearest excited neighbours on the same border.
void border_values(const BorderLayout& border, const Eigen::VectorXd& c, const std::vector<bool>& excited,
                   std::vector<double>& x, std::vector<double>& u) {
  x = border.x;
  u.clear();
  std::vector<bool> known;
  for (int p : border.param) {
    u.push_back(p < 0 ? 0.0 : c(p));
    known.push_back(p < 0 || excited[static_cast<std::size_t>(p)]);
  }
  for (std::size_t i = 0; i < u.size(); ++i) {
    if (known[i]) continue;
    std::size_t lo = i, hi = i;
    while (lo > 0 && !known[lo]) --lo;
    while (hi + 1 < u.size() && !known[hi]) ++hi;
    if (!known[lo]) lo = hi;
    if (!known[hi]) hi = lo;
    const double f = hi == lo ? 0.0 : (x[i] - x[lo]) / (x[hi] - x[lo]);
    u[i] = u[lo] + f * (u[hi] - u[lo]);
  }
}

// The parameter vector of `warm` in this layout's columns (a, the products b_i c_k, kappa0, kappa1), if `warm` has
// the same border tables: a rank-1 start for the Gauss-Newton fit that needs no unrestricted solution.
std::optional<Eigen::VectorXd> warm_theta(const JointModel& warm, const Layout& layout, int n, int P, int cols,
                                          const ModelStructure& structure) {
  if (!warm.ok || warm.n != n || warm.descending_u.size() != layout.descending.x.size() ||
      warm.ascending_u.size() != layout.ascending.x.size() || warm.b.size() != static_cast<std::size_t>(n)) {
    return std::nullopt;
  }
  const Eigen::VectorXd c = detail::border_parameters(warm, layout);
  Eigen::VectorXd theta = Eigen::VectorXd::Zero(cols);
  for (int i = 0; i < n; ++i) {
    theta(i) = warm.a[static_cast<std::size_t>(i)];
    theta.segment(n + i * P, P) = warm.b[static_cast<std::size_t>(i)] * c;
  }
  theta(n + n * P) = warm.kappa0;
  if (structure.drift) theta(n + n * P + 1) = warm.kappa1;
  return theta;
}

// One fit for a fixed basis (regime sequence). `g` is regression_shape(config.n, layout.parameters, data,
// structure), the same for every fit of one fit_joint_model. `instruments_y`, when given, replaces y in the
// instruments; `warm`, when given, may start the rank-1 fit (warm_theta).
JointModel fit_with_basis(const ExperimentConfig& config, const Layout& layout, const FlatRecording& data,
                          const ModelStructure& structure, const RegressionShape& g, const Basis& phi,
                          const std::vector<double>* instruments_y, const JointModel* warm = nullptr,
                          const detail::ConsistencyRows* consistency = nullptr) {
  const int n = config.n;
  const int P = layout.parameters;
  const int cols = g.cols;
  JointModel model;
  model.structure = structure;
  model.n = n;
  model.v_min = config.v_min;
  model.v_max = config.v_max;
  model.rows = g.rows.size();
  model.parameters = cols;
  if (g.rows.size() <= static_cast<std::size_t>(cols)) {
    model.failure = fmt::format("{} identification rows for {} parameters", g.rows.size(), cols);
    return model;
  }
  const std::vector<detail::LagGroup> groups = detail::lag_groups(data, phi);
  NormalEquations ne = normal_equations(g, data, structure, phi, groups, instruments_y);
  const bool smoothed = !layout.stencils.empty() && structure.border_smoothness > 0;
  const ExcitedColumns columns = excited_columns(ne.energy, n, P, cols, smoothed);
  add_smoothness_prior(layout, n, P, structure.border_smoothness, ne);
  if (consistency != nullptr) detail::add_consistency_rows(*consistency, n, P, ne);
  const auto& keep = columns.keep;
  model.parameters = static_cast<int>(keep.size());
  // With the smoothness prior every column is kept: the equations are taken as they are (copying ~360 columns
  // through an index list cost a fifth of the fit).
  const bool all_kept = keep.size() == static_cast<std::size_t>(cols);
  const Eigen::MatrixXd zx = all_kept ? std::move(ne.zx) : Eigen::MatrixXd(ne.zx(keep, keep));
  const Eigen::VectorXd zy = all_kept ? std::move(ne.zy) : Eigen::VectorXd(ne.zy(keep));
  // The finer tables' products have many border columns: their unrestricted fit is that of n free borders (RSS
  // and lambda profile far flatter than the rank-1 model's), so the rank-1 model is fitted by least squares.
  const bool rank_one = instruments_y == nullptr && n >= 2 && structure.border_segments > 1;
  Eigen::VectorXd theta;
  // From a model with the same tables (the previous pass of a regime iteration, a neighbouring lambda), the rank-1
  // fit starts there and skips the unrestricted solution (a Cholesky factorisation of ~350 columns at n = 3, m = 6,
  // most of the fit's cost). If no step improves on the start, the fit is done from the unrestricted solution too.
  if (rank_one && warm != nullptr) {
    if (const auto start = warm_theta(*warm, layout, n, P, cols, structure)) {
      Eigen::VectorXd kept = Eigen::VectorXd::Zero(cols);  // the columns left out stay zero
      for (Eigen::Index k : keep) kept(k) = (*start)(k);
      if (refine_rank_one(zx, zy, keep, n, P, ne.yy, g.rows.size(), kept) > 0) theta = std::move(kept);
    }
  }
  if (theta.size() == 0) {
    const std::optional<Eigen::VectorXd> reduced = solve_normal_equations(zx, zy, instruments_y != nullptr,
                                                                          model.failure);
    if (!reduced) return model;
    theta = Eigen::VectorXd::Zero(cols);
    for (std::size_t i = 0; i < keep.size(); ++i) theta(keep[i]) = (*reduced)(static_cast<Eigen::Index>(i));
    if (rank_one) refine_rank_one(zx, zy, keep, n, P, ne.yy, g.rows.size(), theta);
  }
  const std::vector<double> fitted = detail::fitted_values(g, data, structure, groups, theta);
  model.residuals.reserve(g.rows.size());
  for (std::size_t r = 0; r < g.rows.size(); ++r) {
    const double e = data.y[g.rows[r]] - fitted[r];
    model.residuals.push_back(e);
    model.rss += e * e;
  }
  model.residual_t = g.rows;
  model.residual_variance = model.rss / static_cast<double>(g.rows.size() - keep.size());
  model.a.assign(theta.data(), theta.data() + n);
  Eigen::MatrixXd products(n, P);
  for (int i = 0; i < n; ++i) products.row(i) = theta.segment(n + i * P, P).transpose();
  model.kappa0 = theta(n + n * P);
  model.kappa1 = structure.drift ? theta(n + n * P + 1) : 0.0;

  // Best rank-1 factorisation b c' of the products, scaled so that C~_d(v_min) = c_0 = -1 (3.11c).
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(products, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd s = svd.singularValues();
  Eigen::VectorXd c = svd.matrixV().col(0);
  Eigen::VectorXd b = s(0) * svd.matrixU().col(0);
  model.rank_one_ratio = s.size() > 1 && s(0) > 0 ? s(1) / s(0) : 0.0;
  if (!(ne.energy(n) > 0) || !(std::abs(c(0)) > 1e-9 * c.norm())) {
    model.failure = "degenerate borders: the estimated u_m equals u_M";
    return model;
  }
  const double scale = -1.0 / c(0);
  c *= scale;
  b /= scale;
  model.b.assign(b.data(), b.data() + n);
  border_values(layout.descending, c, columns.excited, model.descending_v, model.descending_u);
  border_values(layout.ascending, c, columns.excited, model.ascending_v, model.ascending_u);
  if (structure.non_negative_play && structure.op == OperatorKind::kBacklash && structure.border_segments > 1) {
    detail::give_non_negative_play(model);
  }
  model.ok = true;
  return model;
}

}  // namespace

FlatRecording flatten(const Recording& recording) {
  FlatRecording f;
  for (Phase p : recording.order()) {
    for (const Sample& s : recording.phase(p)) {
      f.v.push_back(s.v);
      f.y.push_back(s.y);
      f.phase.push_back(p);
    }
  }
  return f;
}

double JointModel::a_sum() const {
  double s = 1.0;
  for (double x : a) s += x;
  return s;
}

double JointModel::drift_total() const { return kappa1 / a_sum(); }

std::vector<double> effective_input(const std::vector<double>& v, const ModelStructure& structure) {
  std::vector<double> w(v.size());
  const auto d = static_cast<std::size_t>(std::max(structure.delay, 0));
  const double lambda = structure.input_lag;
  double state = v.empty() ? 0.0 : v[0];
  for (std::size_t t = 0; t < v.size(); ++t) {
    const double delayed = t >= d ? v[t - d] : v[0];
    state = lambda * state + (1.0 - lambda) * delayed;
    w[t] = lambda == 0.0 ? delayed : state;
  }
  return w;
}

JointModel fit_joint_model(const ExperimentConfig& config, const FlatRecording& data, const ModelStructure& structure,
                           const JointModel* initial, bool only_from_initial) {
  const Layout layout = make_layout(config, std::max(structure.border_segments, 1));
  const std::vector<double> w = effective_input(data.v, structure);
  const RegressionShape shape = regression_shape(config.n, layout.parameters, data, structure);
  ModelStructure ls_structure = structure;
  ls_structure.instrumental = false;
  ls_structure.output_error = false;
  // A backlash's regimes depend on its borders: starting from a first guess of the regimes, refit until they no
  // longer change or a refit no longer fits better (a poor first model, e.g. of a plant with an unmodelled effect,
  // can have borders that make its backlash hold where the plant moves, leaving border points unexcited). Going on
  // after a refit that does not improve (up to 8 passes, as before session 6) cost 2.4 times the fits in the
  // slowest diagnoses; stopping lost 1 hit of 260 tuning cases on curved borders, none of 180 on linear ones.
  // First guesses: the switch's regimes (exact for the nominal experiments, where F acts as a static map) and,
  // when given, the regimes of `initial` (e.g. the nominal fit, a better start once the input is filtered).
  // With structure.regime_consistency, each fit for given regimes phi (from `source`'s borders) is refitted with
  // penalty rows until the model's own backlash takes phi's regimes, or kConsistencyRounds; `consistent` says
  // whether it does in the end.
  const bool consistency = structure.regime_consistency && structure.op == OperatorKind::kBacklash;
  const auto fit_regimes = [&](const Basis& phi, const JointModel* source, bool& consistent) {
    JointModel m = fit_with_basis(config, layout, data, ls_structure, shape, phi, nullptr, source);
    consistent = false;
    if (!consistency) return m;
    std::vector<char> sticky(w.size(), 0);
    for (int round = 0; round <= detail::kConsistencyRounds && m.ok; ++round) {
      detail::ConsistencyRows rows;
      std::vector<char> used(w.size(), 0);
      const int broken = detail::regime_violations(layout, w, data, phi, source, m, sticky, used, rows);
      if (broken == 0) {
        consistent = true;
        break;
      }
      if (round == detail::kConsistencyRounds) break;
      for (std::size_t t = 0; t < used.size(); ++t) sticky[t] = sticky[t] || used[t];
      JointModel next = fit_with_basis(config, layout, data, ls_structure, shape, phi, nullptr, &m, &rows);
      if (!next.ok) break;
      m = std::move(next);
    }
    return m;
  };
  const auto fit_from = [&](const JointModel* start) {
    Basis phi = operator_basis(layout, w, structure.op, start);
    bool consistent = false;
    JointModel model = fit_regimes(phi, start, consistent);
    // A fit whose own backlash takes the regimes it was fitted with ends the iteration. Each pass starts from the
    // best fit so far, which is also the last one: a pass that does not improve ends the iteration.
    if (consistent) return std::pair{std::move(model), std::move(phi)};
    for (int pass = 0; pass < 8 && model.ok && structure.op == OperatorKind::kBacklash; ++pass) {
      Basis next = operator_basis(layout, w, structure.op, &model);
      if (next == phi) break;
      JointModel refitted = fit_regimes(next, &model, consistent);
      if (!consistent && (!refitted.ok || !(refitted.rss < model.rss))) break;
      model = std::move(refitted);
      phi = std::move(next);
      if (consistent) break;
    }
    return std::pair{std::move(model), std::move(phi)};
  };
  const bool from_initial = initial != nullptr && initial->ok && structure.op == OperatorKind::kBacklash;
  // With two starts, the second runs on a second thread (the two iterations share nothing but their inputs).
  std::future<std::pair<JointModel, Basis>> second;
  if (from_initial && !only_from_initial) second = std::async(std::launch::async, fit_from, initial);
  auto [model, phi] = fit_from(from_initial && only_from_initial ? initial : nullptr);
  if (from_initial && only_from_initial && !model.ok) {
    // The one start failed (e.g. its regimes leave a border point the fit needs unexcited): try the other.
    std::tie(model, phi) = fit_from(nullptr);
  } else if (second.valid()) {
    auto [other, other_phi] = second.get();
    // With regime consistency the starts are compared by their own one-step error: a fit that breaks its regimes
    // can have the lower regression error.
    const auto error = [&](const JointModel& m) { return consistency ? self_consistent_rss(m, data) : m.rss; };
    if (other.ok && (!model.ok || error(other) < error(model))) {
      model = std::move(other);
      phi = std::move(other_phi);
    }
  }
  if (structure.regime_search && structure.op == OperatorKind::kBacklash && model.ok) {
    const detail::FitForRegimes refit = [&](const Basis& regimes, const JointModel& warm) {
      return fit_with_basis(config, layout, data, ls_structure, shape, regimes, nullptr, &warm);
    };
    detail::RegimeSearch searched = detail::search_regimes(config, layout, data, w, std::move(model), std::move(phi),
                                                           refit);
    model = std::move(searched.model);
    phi = std::move(searched.phi);
  }
  if (!structure.instrumental || !model.ok) return model;
  // Instrumental variables: the noise-free simulated output of the least-squares model replaces y in the
  // instruments, so they are uncorrelated with a coloured disturbance (Soderstrom & Stoica, Ch. 8). Two passes.
  // If the least-squares model is unstable (its simulation diverges), the delayed operator outputs replace the
  // simulated outputs: u~(t - n - i) is as uncorrelated with the disturbance, only less correlated with y.
  const JointModel ls_model = model;
  for (int pass = 0; pass < 2 && model.ok; ++pass) {
    std::vector<double> x = simulate_segment(model, data, 0, data.size());
    if (!std::all_of(x.begin(), x.end(), [](double value) { return std::isfinite(value); })) {
      const std::vector<double> u = operator_output(ls_model, data);
      const auto lag = static_cast<std::size_t>(config.n);
      for (std::size_t t = 0; t < x.size(); ++t) x[t] = t >= lag ? u[t - lag] : u[0];
    }
    JointModel iv = fit_with_basis(config, layout, data, structure, shape, phi, &x);
    if (!iv.ok) {
      if (pass == 0) return iv;
      break;
    }
    model = std::move(iv);
  }
  // Output error where the borders are the experiment's abscissas (a few parameters; the finer tables' hundreds
  // would make each step a large system); the structure then says which estimator the model is.
  model.structure.output_error = false;
  if (structure.output_error && structure.border_segments <= 1 && model.ok) {
    if (std::optional<JointModel> oe = detail::output_error_fit(model, ls_model, layout, data)) model = std::move(*oe);
  }
  return model;
}

}  // namespace lashid::sim
