// One model extended by one more cause, and the evidence on it (see diagnosis_candidates.hpp).
#include "diagnosis_candidates.hpp"

#include <algorithm>
#include <cmath>
#include <future>
#include <limits>
#include <utility>
#include <vector>

#include "lashid/stats/statistics.hpp"
#include "two_threads.hpp"

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
  // Each delay's fits on two threads (they do not depend on each other), judged in order of the delay.
  const auto delays = static_cast<std::size_t>(std::max(options.max_delay, 0));
  std::vector<JointModel> fits(delays);
  std::vector<double> simulation(delays, std::numeric_limits<double>::infinity());
  on_two_threads(delays, [&](std::size_t i) {
    ModelStructure s = current.structure;
    s.delay = static_cast<int>(i) + 1;
    fits[i] = fit_joint_model(config, data, s, &current);
    if (!fits[i].ok || !options.delay_by_simulation) return;
    s.instrumental = true;
    const JointModel iv = fit_joint_model(config, data, s, &fits[i]);
    if (iv.ok) simulation[i] = identification_simulation_sse(iv, data);
  });
  JointModel by_rss = current, by_simulation;
  double simulation_sse = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < delays; ++i) {
    JointModel& m = fits[i];
    if (!m.ok) continue;
    if (options.delay_by_simulation && simulation[i] < simulation_sse) {
      simulation_sse = simulation[i];
      by_simulation = m;
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

bool significant(double likelihood_ratio, const DiagnosisOptions& options) {
  return stats::chi2_sf(std::max(likelihood_ratio, 0.0), 1.0) < options.structural_p;
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

double aperiodic_correlation(const JointModel& model, const FlatRecording& data, int period) {
  const std::vector<double>& e = model.residuals;
  const std::vector<std::size_t>& t = model.residual_t;
  if (e.size() <= static_cast<std::size_t>(kResidualLags) || period < 1) return 0.0;
  std::vector<double> aperiodic;
  aperiodic.reserve(e.size());
  // Each run of residuals from one phase loses its own periodic mean, its phase counted from the phase's start.
  for (std::size_t begin = 0; begin < e.size();) {
    const Phase phase = data.phase[t[begin]];
    std::size_t start = t[begin];
    while (start > 0 && data.phase[start - 1] == phase) --start;
    std::size_t end = begin;
    while (end < e.size() && data.phase[t[end]] == phase) ++end;
    std::vector<std::size_t> since_start(t.begin() + static_cast<std::ptrdiff_t>(begin),
                                         t.begin() + static_cast<std::ptrdiff_t>(end));
    for (std::size_t& s : since_start) s -= start;
    const bool pulses = phase == Phase::kDis || phase == Phase::kAis;
    const std::vector<double> run = stats::without_periodic_mean(
        std::span(e).subspan(begin, end - begin), since_start, pulses ? static_cast<std::size_t>(period) : 1);
    aperiodic.insert(aperiodic.end(), run.begin(), run.end());
    begin = end;
  }
  return stats::ljung_box(aperiodic, kResidualLags).statistic / static_cast<double>(aperiodic.size());
}

double sse(std::span<const double> a, std::span<const double> b) {
  double s = 0;
  for (std::size_t i = 0; i < a.size(); ++i) s += (a[i] - b[i]) * (a[i] - b[i]);
  return s;
}

ModelStructure coloured_estimator(ModelStructure s, const DiagnosisOptions& options) {
  s.instrumental = true;
  s.output_error = options.coloured_output_error;
  s.output_error_restarts = options.coloured_output_error_restarts;
  return s;
}

double flip_error_ratio(std::span<const double> before_val, std::span<const double> after_val,
                        std::span<const double> measured) {
  const double before_sse = sse(before_val, measured), after_sse = sse(after_val, measured);
  constexpr double kInf = std::numeric_limits<double>::infinity();
  return std::isfinite(before_sse) ? after_sse / before_sse : (std::isfinite(after_sse) ? 0.0 : kInf);
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
      c.lag_searched_on = current.structure;
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
      c.model = fit_joint_model(config, data, coloured_estimator(s, options), &current);
      c.parameters.instrumental_variables = true;
      c.parameters.output_error = c.model.structure.output_error;
      break;
    case Cause::kOperatorType:
      // No starting regimes from `current`: they are the other operator's.
      s.op = other_operator(s.op);
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
  c.fit_val = simulation_fit(c.model, data, val_begin, val_end, &simulated);
  c.identification = residuals(c.model, data, false);
  c.likelihood_ratio = likelihood_ratio(before, c.model);
  if (c.cause == Cause::kOperatorType) {
    // Same fit on the identification phases when the experiments make F static; only val can tell.
    const std::span<const double> measured(data.y.data() + val_begin, val_end - val_begin);
    // Against a model whose val simulation diverges, the flipped operator counts only if its own does not.
    const double ratio = flip_error_ratio(before_val, simulated, measured);
    c.statistic = std::isfinite(ratio) ? ratio : std::numeric_limits<double>::infinity();
    c.p_value = ratio < options.operator_sse_ratio ? 0.0 : 1.0;
  } else if (c.cause != Cause::kColoredNoise) {
    c.statistic = c.likelihood_ratio;
    c.p_value = stats::chi2_sf(std::max(c.statistic, 0.0), 1.0);
  }
}

std::vector<CandidateCause> candidates_for(const std::vector<Cause>& causes,
                                           const std::function<CandidateCause(Cause)>& make) {
  std::vector<std::future<CandidateCause>> made;
  made.reserve(causes.size());
  for (Cause cause : causes) made.push_back(std::async(std::launch::async, make, cause));
  std::vector<CandidateCause> out;
  out.reserve(causes.size());
  for (auto& m : made) out.push_back(m.get());
  return out;
}

}  // namespace lashid::sim::detail
