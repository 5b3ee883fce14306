#include "lashid/diagnose/diagnosis.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

namespace lashid::sim {

namespace {

double likelihood_ratio(const JointModel& nominal, const JointModel& extended) {
  if (!extended.ok || !(extended.rss > 0)) return 0.0;
  return static_cast<double>(nominal.rows) * std::log(nominal.rss / extended.rss);
}

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

// One-step residuals of `model` on the identification samples (or on val), with the aligned inputs.
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
               std::vector<double>* simulated = nullptr) {
  std::vector<double> sim = simulate_segment(model, data, begin, end);
  const std::span<const double> measured(data.y.data() + begin, end - begin);
  // An unstable model's simulation diverges: its fit is -infinity (null in JSON), not an error.
  const bool finite = std::all_of(sim.begin(), sim.end(), [](double x) { return std::isfinite(x); });
  const double fit = finite ? stats::fit_percent(measured, sim) : -std::numeric_limits<double>::infinity();
  if (simulated != nullptr) *simulated = std::move(sim);
  return fit;
}

double sse(const std::vector<double>& a, std::span<const double> b) {
  double s = 0;
  for (std::size_t i = 0; i < a.size(); ++i) s += (a[i] - b[i]) * (a[i] - b[i]);
  return s;
}

// Input lag: RSS(lambda) on a 0.05 grid, then a golden-section refinement around the best grid point.
CandidateCause input_lag_candidate(const ExperimentConfig& config, const FlatRecording& data,
                                   const JointModel& nominal, const DiagnosisOptions& options) {
  ModelStructure s = nominal.structure;
  const auto fit = [&](double lambda) {
    s.input_lag = lambda;
    return fit_joint_model(config, data, s, &nominal);
  };
  JointModel best = nominal;
  double best_lambda = 0;
  for (double lambda = 0.05; lambda <= options.max_input_lag + 1e-9; lambda += 0.05) {
    JointModel m = fit(lambda);
    if (m.ok && m.rss < best.rss) {
      best = std::move(m);
      best_lambda = lambda;
    }
  }
  if (best_lambda > 0) {
    double lo = std::max(best_lambda - 0.05, 0.0), hi = std::min(best_lambda + 0.05, options.max_input_lag);
    const double g = (std::sqrt(5.0) - 1.0) / 2.0;
    for (int it = 0; it < 10; ++it) {
      const double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
      JointModel m1 = fit(x1), m2 = fit(x2);
      const double inf = std::numeric_limits<double>::infinity();
      const double r1 = m1.ok ? m1.rss : inf, r2 = m2.ok ? m2.rss : inf;
      if (r1 < r2) {
        hi = x2;
        if (r1 < best.rss) best = std::move(m1);
      } else {
        lo = x1;
        if (r2 < best.rss) best = std::move(m2);
      }
    }
  }
  CandidateCause c;
  c.cause = Cause::kInputLag;
  c.model = std::move(best);
  c.parameters.lambda = c.model.structure.input_lag;
  return c;
}

CandidateCause dead_time_candidate(const ExperimentConfig& config, const FlatRecording& data,
                                   const JointModel& nominal, const DiagnosisOptions& options) {
  CandidateCause c;
  c.cause = Cause::kDeadTime;
  c.model = nominal;
  for (int d = 1; d <= options.max_delay; ++d) {
    ModelStructure s = nominal.structure;
    s.delay = d;
    JointModel m = fit_joint_model(config, data, s, &nominal);
    if (m.ok && m.rss < c.model.rss) c.model = std::move(m);
  }
  c.parameters.delay = c.model.structure.delay;
  return c;
}

// The recording must hold all five phases, match the config, and give the residual tests enough val samples.
void check_diagnosable(const ExperimentConfig& config, const Recording& recording, std::string_view data_name) {
  for (Phase p : kAllPhases) {
    if (!recording.has(p)) {
      throw DataError(data_name, fmt::format("diagnose needs all five phases; '{}' is missing", to_string(p)));
    }
  }
  check_recording_matches(config, recording, data_name);
  const std::size_t min_val = 10 * static_cast<std::size_t>(kResidualLags);
  if (recording.phase(Phase::kVal).size() < min_val) {
    throw DataError(data_name, fmt::format("phase 'val' has {} samples; the residual tests need at least {}",
                                           recording.phase(Phase::kVal).size(), min_val));
  }
}

// The model extended by each cause, fitted on the identification phases (input lag and dead time by their own
// searches; drift, instrumental variables and the other operator type by one fit each).
std::vector<CandidateCause> fit_candidates(const ExperimentConfig& config, const FlatRecording& data,
                                           const JointModel& nominal, const DiagnosisOptions& options) {
  std::vector<CandidateCause> candidates;
  candidates.push_back(input_lag_candidate(config, data, nominal, options));
  candidates.push_back(dead_time_candidate(config, data, nominal, options));
  ModelStructure nominal_structure;
  nominal_structure.op = config.op;
  {
    CandidateCause c;
    c.cause = Cause::kSensorDrift;
    ModelStructure s = nominal_structure;
    s.drift = true;
    c.model = fit_joint_model(config, data, s);
    c.parameters.drift_total = c.model.drift_total();
    candidates.push_back(std::move(c));
  }
  {
    CandidateCause c;
    c.cause = Cause::kColoredNoise;
    ModelStructure s = nominal_structure;
    s.instrumental = true;
    c.model = fit_joint_model(config, data, s);
    c.parameters.instrumental_variables = true;
    candidates.push_back(std::move(c));
  }
  {
    CandidateCause c;
    c.cause = Cause::kOperatorType;
    ModelStructure s = nominal_structure;
    s.op = config.op == OperatorKind::kSwitch ? OperatorKind::kBacklash : OperatorKind::kSwitch;
    c.model = fit_joint_model(config, data, s);
    c.parameters.op = s.op;
    candidates.push_back(std::move(c));
  }
  return candidates;
}

// Evidence per candidate: val fit, residual analysis, likelihood ratio against the nominal model, and the statistic
// the decision reads (the val error ratio for the operator type, which the identification phases cannot judge).
void score_candidates(Diagnosis& d, const FlatRecording& data, std::span<const double> measured,
                      const DiagnosisOptions& options) {
  for (CandidateCause& c : d.candidates) {
    if (!c.model.ok) continue;
    c.fit_val = val_fit(c.model, data, d.val_begin, d.val_end);
    c.identification = residuals(c.model, data, false);
    c.likelihood_ratio = likelihood_ratio(d.nominal, c.model);
    if (c.cause == Cause::kOperatorType) {
      // Same fit on the identification phases (the experiments make F static); only val can tell.
      std::vector<double> sim = simulate_segment(c.model, data, d.val_begin, d.val_end);
      const double nominal_sse = sse(d.val_nominal, measured);
      const double ratio = std::isfinite(nominal_sse) ? sse(sim, measured) / nominal_sse : 0.0;
      c.statistic = ratio;
      c.p_value = ratio < options.operator_sse_ratio ? 0.0 : 1.0;
    } else if (c.cause != Cause::kColoredNoise) {
      c.statistic = likelihood_ratio(d.nominal, c.model);
      c.p_value = stats::chi2_sf(std::max(c.statistic, 0.0), 1.0);
    }
  }
}

// Decision: the strongest structural extension that is significant and leaves white residuals; else a flipped
// operator that halves the val error; else coloured noise if the residuals are not white; else none (nullptr).
const CandidateCause* decide(const Diagnosis& d, const DiagnosisOptions& options) {
  const CandidateCause* chosen = nullptr;
  // The operator type competes here too: the experiments' pulses usually make F static, but not always (e.g.
  // closely spaced pulses), and then the identification phases themselves tell switch from backlash.
  for (const CandidateCause& c : d.candidates) {
    if (c.cause == Cause::kColoredNoise || !c.model.ok) continue;
    // The extension must explain the residual correlation: white residuals, or a Ljung-Box statistic cut to a
    // fraction of the nominal one (a coloured disturbance leaves most of it whatever the structure).
    const bool explains = c.identification.whiteness.p_value >= options.white_p ||
                          c.identification.whiteness.statistic < options.whiteness_ratio * d.identification.whiteness.statistic;
    if (stats::chi2_sf(std::max(c.likelihood_ratio, 0.0), 1.0) >= options.structural_p || !explains) continue;
    if (chosen == nullptr || c.likelihood_ratio > chosen->likelihood_ratio) chosen = &c;
  }
  const auto find = [&](Cause cause) -> const CandidateCause& {
    return *std::find_if(d.candidates.begin(), d.candidates.end(), [&](const auto& c) { return c.cause == cause; });
  };
  // A wrong operator type leaves the identification residuals white (the experiments make F static).
  if (chosen == nullptr && d.identification.whiteness.p_value >= options.white_p &&
      find(Cause::kOperatorType).model.ok && find(Cause::kOperatorType).p_value == 0.0) {
    chosen = &find(Cause::kOperatorType);
  }
  if (chosen == nullptr && d.identification.whiteness.p_value < options.white_p &&
      find(Cause::kColoredNoise).model.ok) {
    chosen = &find(Cause::kColoredNoise);
  }
  return chosen;
}

}  // namespace

Diagnosis diagnose(const ExperimentConfig& config, const Recording& recording, std::string_view data_name,
                   const DiagnosisOptions& options) {
  check_diagnosable(config, recording, data_name);
  // A float32 device's recording (lashid hil --record) holds float(V_j): the model is fitted on the levels.
  const FlatRecording data = flatten(snap_to_configured_levels(config, recording));
  Diagnosis d;
  for (std::size_t t = 0; t < data.size(); ++t) {
    if (data.phase[t] != Phase::kVal) continue;
    if (d.val_end == 0) d.val_begin = t;
    d.val_end = t + 1;
  }

  // The paper's estimates per scheme, and their disagreement on A and B (Remark 3b, as the firmware reports it).
  d.dis = identify_scheme(config, recording, est::Scheme::kDescending, {}, data_name);
  d.ais = identify_scheme(config, recording, est::Scheme::kAscending, {}, data_name);
  if (d.dis.status == est::Status::kOk && d.ais.status == est::Status::kOk) {
    d.remark3b_z = cross_check(config, d.dis, d.ais).max_z;
  }

  ModelStructure nominal_structure;
  nominal_structure.op = config.op;
  d.nominal = fit_joint_model(config, data, nominal_structure);
  if (!d.nominal.ok) throw std::runtime_error(fmt::format("{}: the nominal model cannot be fitted: {}", data_name,
                                                          d.nominal.failure));
  d.identification = residuals(d.nominal, data, false);
  d.validation = residuals(d.nominal, data, true);
  d.fit_nominal = val_fit(d.nominal, data, d.val_begin, d.val_end, &d.val_nominal);
  const std::span<const double> measured(data.y.data() + d.val_begin, d.val_end - d.val_begin);

  // Structural candidates are judged by the likelihood ratio on the identification phases only.
  d.candidates = fit_candidates(config, data, d.nominal, options);
  score_candidates(d, data, measured, options);
  const CandidateCause* chosen = decide(d, options);
  if (chosen == nullptr) {
    d.cause = Cause::kNone;
    d.extended = d.nominal;
    d.fit_extended = d.fit_nominal;
    d.val_extended = d.val_nominal;
  } else {
    d.cause = chosen->cause;
    d.parameters = chosen->parameters;
    d.extended = chosen->model;
    d.fit_extended = val_fit(d.extended, data, d.val_begin, d.val_end, &d.val_extended);
  }
  d.val_v.assign(data.v.begin() + static_cast<std::ptrdiff_t>(d.val_begin),
                 data.v.begin() + static_cast<std::ptrdiff_t>(d.val_end));
  d.val_measured.assign(measured.begin(), measured.end());
  d.findings = describe_findings(d);
  return d;
}

}  // namespace lashid::sim
