// One model extended by one more cause, and the evidence on it (see diagnosis_candidates.hpp).
#include "diagnosis_candidates.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "lashid/stats/metrics.hpp"

namespace lashid::sim::detail {

namespace {

ResidualAnalysis analyse(const std::vector<double>& e, const std::vector<double>& v) {
  ResidualAnalysis r;
  r.samples = e.size();
  r.autocorrelation = stats::autocorrelation(e, kResidualLags);
  r.cross_correlation = stats::cross_correlation(e, v, kResidualLags);
  r.band = stats::correlation_band(e.size(), 0.99);
  r.whiteness = stats::ljung_box(e, kResidualLags);
  r.independence = stats::cross_correlation_test(e, v, kResidualLags);
  r.trend = stats::linear_trend(e);
  return r;
}

double rss_or_infinity(const JointModel& m) { return m.ok ? m.rss : std::numeric_limits<double>::infinity(); }

// Golden-section search of lambda in [a, b] at a given border resolution; returns the best fit seen (or `best`).
template <class Fit>
JointModel golden_lambda(Fit fit, double a, double b, int iterations, JointModel best) {
  const double g = (std::sqrt(5.0) - 1.0) / 2.0;
  for (int it = 0; it < iterations; ++it) {
    const double x1 = b - g * (b - a), x2 = a + g * (b - a);
    JointModel m1 = fit(x1), m2 = fit(x2);
    const double r1 = rss_or_infinity(m1), r2 = rss_or_infinity(m2);
    if (r1 < r2) {
      b = x2;
      if (r1 < rss_or_infinity(best)) best = std::move(m1);
    } else {
      a = x1;
      if (r2 < rss_or_infinity(best)) best = std::move(m2);
    }
  }
  return best;
}

// One fit per lambda along a path: each starts from the previous lambda's regimes (continuation) and, for a
// backlash, also from `current`'s, keeping the lower RSS. Started from `current` alone, a backlash's regime
// iteration ends in a poor fixed point at some lambdas (RSS 3 to 50 times the neighbours' on tuning seeds).
struct LagPath {
  std::vector<double> lambda;
  std::vector<JointModel> model;
  std::vector<double> fit_val;
};

template <class Fit>
LagPath fit_lag_path(Fit fit, const JointModel& current, const std::vector<double>& lambdas, const FlatRecording& data,
                     std::pair<std::size_t, std::size_t> val, bool two_starts) {
  LagPath path;
  const JointModel* previous = &current;
  for (double lambda : lambdas) {
    JointModel m = fit(lambda, previous);
    if (two_starts && previous != &current && current.structure.op == OperatorKind::kBacklash) {
      JointModel again = fit(lambda, &current);
      if (again.ok && (!m.ok || again.rss < m.rss)) m = std::move(again);
    }
    if (!m.ok) continue;
    path.lambda.push_back(lambda);
    path.fit_val.push_back(val_fit(m, data, val.first, val.second));
    path.model.push_back(std::move(m));
    previous = &path.model.back();
  }
  return path;
}

std::size_t best_rss(const LagPath& p) {
  std::size_t best = 0;
  for (std::size_t i = 1; i < p.model.size(); ++i) {
    if (p.model[i].rss < p.model[best].rss) best = i;
  }
  return best;
}

// The lambda whose model simulates val best among those the identification phases do not reject: N ln(RSS /
// min_rss) <= window.
std::size_t best_val(const LagPath& p, double min_rss, double window) {
  std::size_t best = p.model.size();
  for (std::size_t i = 0; i < p.fit_val.size(); ++i) {
    const double lr = static_cast<double>(p.model[i].rows) * std::log(p.model[i].rss / min_rss);
    if (lr <= window && (best == p.model.size() || p.fit_val[i] > p.fit_val[best])) best = i;
  }
  return best;
}

// Input lag. Two border models:
// - coarse: borders linear between the experiment's abscissas; RSS(lambda) on a 0.05 grid, then golden section
//   (+-0.05). On borders linear between the levels it is exact and pins lambda sharply.
// - fine: options.lag_border_segments points per interval, held smooth by a prior where the data are thin. The lag
//   moves the operator's input between the levels, where a real border is curved, so lambda needs a border model
//   that is right there; but with a flexible border the identification phases barely tell lambda apart (every
//   pulse starts from the same extreme level: a different lambda and a reshaped border give the same outputs; the
//   RSS profile is flat to 1 % over +-0.15 on curved tuning seeds, and its minimum is biased upward). The val
//   phase, whose moves join every pair of levels, does tell them apart: lambda is the one whose model simulates
//   val best, on a 0.05 grid and then a 0.01 grid (+-0.02) around it.
// The fine model is used if BIC prefers it at its RSS minimum (N ln(RSS_coarse / RSS_fine) > extra parameters x
// ln N) or if it simulates val more than options.lag_fine_val_gain points better than the coarse one; otherwise
// the coarse model (on borders linear between the levels it is exact and pins lambda better).
JointModel search_input_lag(const ExperimentConfig& config, const FlatRecording& data, const JointModel& current,
                            const DiagnosisOptions& options) {
  const auto fit_with = [&](int segments) {
    return [&, segments](double lambda, const JointModel* start) {
      ModelStructure s = current.structure;
      s.border_smoothness = options.lag_border_smoothness;
      s.input_lag = lambda;
      s.border_segments = segments;
      return fit_joint_model(config, data, s, start, true);
    };
  };
  const auto coarse = fit_with(1);
  const auto fine = fit_with(options.lag_border_segments);
  const double max_lag = options.max_input_lag;
  std::vector<double> grid;
  for (double lambda = 0.05; lambda <= max_lag + 1e-9; lambda += 0.05) grid.push_back(lambda);
  JointModel best_coarse;
  double grid_lambda = 0;
  for (double lambda : grid) {
    JointModel m = coarse(lambda, &current);
    if (m.ok && m.rss < rss_or_infinity(best_coarse)) {
      best_coarse = std::move(m);
      grid_lambda = lambda;
    }
  }
  if (!best_coarse.ok) return current;
  // The coarse model's golden section only where the coarse model is the answer (every fit costs about the same:
  // building the normal equations dominates, whatever the border resolution).
  const auto refined_coarse = [&]() {
    return golden_lambda([&](double l) { return coarse(l, &current); }, std::max(grid_lambda - 0.05, 0.0),
                         std::min(grid_lambda + 0.05, max_lag), options.golden_iterations, best_coarse);
  };
  if (options.lag_border_segments <= 1) return refined_coarse();
  const auto val = val_range(data);
  const LagPath path = fit_lag_path(fine, current, grid, data, val, true);
  if (path.model.empty()) return refined_coarse();
  const JointModel& fine_rss = path.model[best_rss(path)];
  const double samples = static_cast<double>(best_coarse.rows);
  const double gain = samples * std::log(best_coarse.rss / fine_rss.rss);
  const double cost = static_cast<double>(fine_rss.parameters - best_coarse.parameters) * std::log(samples);
  const double min_rss = fine_rss.rss;
  const std::size_t at = best_val(path, min_rss, options.lag_val_window);
  const double coarse_val = val_fit(best_coarse, data, val.first, val.second);
  if (!(gain > cost) && !(path.fit_val[at] > coarse_val + options.lag_fine_val_gain)) return refined_coarse();
  std::vector<double> local;
  for (int k = -2; k <= 2; ++k) {
    const double lambda = path.lambda[at] + 0.01 * k;
    if (k != 0 && lambda > 0.0 && lambda <= max_lag) local.push_back(lambda);
  }
  const LagPath near = fit_lag_path(fine, path.model[at], local, data, val, false);
  const std::size_t near_at = best_val(near, min_rss, options.lag_val_window);
  if (near_at == near.model.size() || near.fit_val[near_at] <= path.fit_val[at]) return path.model[at];
  return near.model[near_at];
}

// Sum of squared simulation errors over the identification phases: a pure simulation from t = 0 (no measured
// output after the first sample, none of val). Under white sensor noise this is the output-error criterion, which
// the equation error's RSS is not.
double identification_simulation_sse(const JointModel& model, const FlatRecording& data) {
  const std::vector<double> sim = simulate_segment(model, data, 0, data.size());
  double s = 0;
  for (std::size_t t = 0; t < data.size(); ++t) {
    if (!data.is_identification(t)) continue;
    const double e = data.y[t] - sim[t];
    if (!std::isfinite(e)) return std::numeric_limits<double>::infinity();
    s += e * e;
  }
  return s;
}

// The delay d = 1..max_delay. By least squares' RSS, sensor noise made it one sample too long in 6 of 40 tuning
// cases of dead_time+colored_noise (1000, 1001, 1011, 1032, 1037, 1039): the equation error is then coloured and
// least squares biased. With options.delay_by_simulation, each delay's structure is refitted by instrumental
// variables and the delay is the one whose IV model simulates the identification phases best (a wrong delay's IV
// fit often diverges); the least-squares model at that delay is returned (IV is the colored_noise extension's).
JointModel search_dead_time(const ExperimentConfig& config, const FlatRecording& data, const JointModel& current,
                            const DiagnosisOptions& options) {
  JointModel by_rss = current, by_simulation;
  double simulation_sse = std::numeric_limits<double>::infinity();
  for (int d = 1; d <= options.max_delay; ++d) {
    ModelStructure s = current.structure;
    s.delay = d;
    JointModel m = fit_joint_model(config, data, s, &current);
    if (!m.ok) continue;
    if (options.delay_by_simulation) {
      s.instrumental = true;
      const JointModel iv = fit_joint_model(config, data, s, &m);
      const double sse = iv.ok ? identification_simulation_sse(iv, data) : std::numeric_limits<double>::infinity();
      if (sse < simulation_sse) {
        simulation_sse = sse;
        by_simulation = m;
      }
    }
    if (by_rss.structure.delay == 0 || m.rss < by_rss.rss) by_rss = std::move(m);
  }
  return by_simulation.ok ? by_simulation : by_rss;
}

}  // namespace

std::pair<std::size_t, std::size_t> val_range(const FlatRecording& data) {
  std::size_t begin = 0, end = 0;
  for (std::size_t t = 0; t < data.size(); ++t) {
    if (data.phase[t] != Phase::kVal) continue;
    if (end == 0) begin = t;
    end = t + 1;
  }
  return {begin, end};
}

double likelihood_ratio(const JointModel& before, const JointModel& after) {
  if (!after.ok || !(after.rss > 0)) return 0.0;
  return static_cast<double>(before.rows) * std::log(before.rss / after.rss);
}

// On the identification phases these are the regression's own residuals (those of the likelihood ratio); on val
// the one-step prediction errors of the factorised model.
ResidualAnalysis residuals(const JointModel& model, const FlatRecording& data, bool validation) {
  if (!validation) {
    std::vector<double> v;
    for (std::size_t t : model.residual_t) v.push_back(data.v[t]);
    return analyse(model.residuals, v);
  }
  const std::vector<double> e_all = prediction_errors(model, data, 0, data.size());
  std::vector<double> e, v;
  for (std::size_t t = static_cast<std::size_t>(model.n); t < data.size(); ++t) {
    if (data.is_identification(t) == validation) continue;
    e.push_back(e_all[t - static_cast<std::size_t>(model.n)]);
    v.push_back(data.v[t]);
  }
  return analyse(e, v);
}

double val_fit(const JointModel& model, const FlatRecording& data, std::size_t begin, std::size_t end,
               std::vector<double>* simulated) {
  std::vector<double> sim = simulate_segment(model, data, begin, end);
  const std::span<const double> measured(data.y.data() + begin, end - begin);
  // An unstable model's simulation diverges: its fit is -infinity (null in JSON), not an error.
  const bool finite = std::all_of(sim.begin(), sim.end(), [](double x) { return std::isfinite(x); });
  const double fit = finite ? stats::fit_percent(measured, sim) : -std::numeric_limits<double>::infinity();
  if (simulated != nullptr) *simulated = std::move(sim);
  return fit;
}

double sse(std::span<const double> a, std::span<const double> b) {
  double s = 0;
  for (std::size_t i = 0; i < a.size(); ++i) s += (a[i] - b[i]) * (a[i] - b[i]);
  return s;
}

CandidateCause extend_model(const ExperimentConfig& config, const FlatRecording& data, const JointModel& current,
                            Cause cause, const DiagnosisOptions& options) {
  CandidateCause c;
  c.cause = cause;
  ModelStructure s = current.structure;
  switch (cause) {
    case Cause::kInputLag:
      c.model = search_input_lag(config, data, current, options);
      c.parameters.lambda = c.model.structure.input_lag;
      break;
    case Cause::kDeadTime:
      c.model = search_dead_time(config, data, current, options);
      c.parameters.delay = c.model.structure.delay;
      break;
    case Cause::kSensorDrift:
      s.drift = true;
      c.model = fit_joint_model(config, data, s, &current);
      c.parameters.drift_total = c.model.drift_total();
      break;
    case Cause::kColoredNoise:
      s.instrumental = true;
      c.model = fit_joint_model(config, data, s, &current);
      c.parameters.instrumental_variables = true;
      break;
    case Cause::kOperatorType:
      // No starting regimes from `current`: they are the other operator's.
      s.op = s.op == OperatorKind::kSwitch ? OperatorKind::kBacklash : OperatorKind::kSwitch;
      c.model = fit_joint_model(config, data, s);
      c.parameters.op = s.op;
      break;
    case Cause::kNone:
      c.model = current;
      break;
  }
  return c;
}

void score_candidate(CandidateCause& c, const JointModel& before, std::span<const double> before_val,
                     const FlatRecording& data, std::size_t val_begin, std::size_t val_end,
                     const DiagnosisOptions& options) {
  if (!c.model.ok) return;
  std::vector<double> simulated;
  c.fit_val = val_fit(c.model, data, val_begin, val_end, &simulated);
  c.identification = residuals(c.model, data, false);
  c.likelihood_ratio = likelihood_ratio(before, c.model);
  if (c.cause == Cause::kOperatorType) {
    // Same fit on the identification phases when the experiments make F static; only val can tell.
    const std::span<const double> measured(data.y.data() + val_begin, val_end - val_begin);
    const double before_sse = sse(before_val, measured);
    const double ratio = std::isfinite(before_sse) ? sse(simulated, measured) / before_sse : 0.0;
    c.statistic = std::isfinite(ratio) ? ratio : std::numeric_limits<double>::infinity();
    c.p_value = ratio < options.operator_sse_ratio ? 0.0 : 1.0;
  } else if (c.cause != Cause::kColoredNoise) {
    c.statistic = c.likelihood_ratio;
    c.p_value = stats::chi2_sf(std::max(c.statistic, 0.0), 1.0);
  }
}

}  // namespace lashid::sim::detail
