// The forward selection of the causes, the steps after it, and colored_noise by exclusion (diagnosis.hpp,
// docs/diagnose.md "Decision").
#include "diagnosis_selection.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <limits>
#include <optional>
#include <utility>

#include "diagnosis_steps.hpp"
#include "lashid/estimator/design.hpp"
#include "two_threads.hpp"

namespace lashid::sim::detail {

namespace {

// How near the top of its search range (DiagnosisOptions::max_input_lag) an input lag's lambda counts as pinned at
// its bound (operator_first).
constexpr double kLambdaNearItsBound = 0.1;

bool white(const ResidualAnalysis& r, const DiagnosisOptions& options) { return r.whiteness.p_value >= options.white_p; }

// The better of a model's least-squares and instrumental-variable val fits (the IV one where it was computed).
double best_fit(double least_squares, double instrumental) {
  return std::isnan(instrumental) ? least_squares : std::max(least_squares, instrumental);
}

// An input lag whose lambda was chosen on val (the finer border tables): choosing it there flatters its val fit.
bool lambda_chosen_on_val(const CandidateCause& c) {
  return c.cause == Cause::kInputLag && c.model.structure.border_segments > 1;
}

// Whether a structural extension of `current` is supported: significant on the identification phases, explaining
// the residual correlation (white residuals, most of the Ljung-Box statistic gone, or a large val gain when a
// coloured disturbance keeps the residuals coloured whatever the structure), and better on val (the val check).
bool structural_accepted(const CandidateCause& c, const CurrentModel& current, const DiagnosisOptions& options) {
  if (!c.model.ok || !detail::significant(c.likelihood_ratio, options)) return false;
  const double val_gain = c.fit_val - current.fit;
  // The IV check: an extension that simulates val no better than the current structure with a coloured
  // disturbance's bias removed (instrumental variables) is absorbing that disturbance, not a missing structure.
  // Like is compared with like: the extension counts with its own IV fit where that is better (a real dead time
  // next to coloured noise: least squares biases its val fit, IV does not).
  const double extended = best_fit(c.fit_val, c.fit_instrumental);
  // An input lag whose lambda was chosen on val must beat the IV fit by options.lag_val_optimism.
  const bool lambda_on_val = lambda_chosen_on_val(c);
  // With output error in the checks, an extension whose residuals are white has left no coloured disturbance to
  // absorb: the check does not apply (a true dead time of one sample lost to the nominal structure's output-error
  // fit, which nearly contains it: tuning seeds 1144 and 1162, residuals white with the delay).
  const bool beats_instrumental =
      !options.instrumental_check || (options.output_error_in_checks && white(c.identification, options)) ||
      extended > current.fit_instrumental + (lambda_on_val ? options.lag_val_optimism : 0.0);
  // The large val gain may also be the IV fits' (a drift under sensor noise: least squares gained 2.5 to 4.8 points
  // on tuning seeds 1030, 1036 and 1039 of sensor_drift+colored_noise, its IV fit more than 5 over the nominal IV).
  const double like_gain = options.instrumental_ranking ? extended - std::max(current.fit, current.fit_instrumental)
                                                        : val_gain;
  const bool explains = white(c.identification, options) ||
                        c.identification.whiteness.statistic <
                            options.whiteness_ratio * current.identification.whiteness.statistic ||
                        std::max(val_gain, like_gain) >= options.explaining_val_gain;
  const double checked_gain = options.instrumental_val_check ? std::max(val_gain, like_gain) : val_gain;
  return explains && checked_gain > options.min_val_gain && beats_instrumental;
}

// Whether two structures have the same causes other than the input lag (the lag's own fields, lambda and the
// border tables, are not compared).
bool same_besides_lag(const ModelStructure& a, const ModelStructure& b) {
  return a.op == b.op && a.delay == b.delay && a.drift == b.drift && a.instrumental == b.instrumental &&
         a.output_error == b.output_error;
}

void accept(Diagnosis& d, CurrentModel& current, const CandidateCause& c, const FlatRecording& data) {
  AddedCause added;
  added.cause = c.cause;
  added.parameters = c.parameters;
  added.likelihood_ratio = c.cause == Cause::kColoredNoise ? 0.0 : c.likelihood_ratio;
  added.fit_before = current.fit;
  added.ljung_box_before = current.identification.whiteness.statistic;
  adopt(current, c.model, d, data);
  if (c.lag_searched_on) current.lag_searched_on = c.lag_searched_on;
  added.fit_after = current.fit;
  added.ljung_box_after = current.identification.whiteness.statistic;
  d.added.push_back(std::move(added));
}

// Whether a flipped operator type is supported: it must bring the val error energy below operator_sse_ratio of
// the current model's (score_candidate's p_value 0). The experiments usually make F act as a static map, so only
// val's reversals tell a switch from a backlash; the structural test also applies when they do not.
bool operator_accepted(const CandidateCause& c, const CurrentModel& current, const DiagnosisOptions& options) {
  return c.model.ok && (c.p_value == 0.0 || structural_accepted(c, current, options));
}

// An input lag found before another cause was fitted without it (a drift, say, biases lambda): once the selection
// is done, lambda is searched again with every other cause in the model, and the refit kept if it simulates val
// better (its val gain is counted in the last step's). A lag added last was searched with all the others in.
void refine_input_lag(Diagnosis& d, CurrentModel& current, const ExperimentConfig& config, const FlatRecording& data,
                      const DiagnosisOptions& options) {
  const auto lag = std::find_if(d.added.begin(), d.added.end(),
                                [](const AddedCause& a) { return a.cause == Cause::kInputLag; });
  if (lag == d.added.end() || std::next(lag) == d.added.end()) return;
  // Nor one whose lambda was searched again on top of everything added after it (lag_with_drift): the same search
  // once more would differ only by its start (session 16: a whole lambda search, up to a quarter of the slowest
  // diagnoses).
  const ModelStructure others = without_cause(current.model.structure, Cause::kInputLag);
  if (current.lag_searched_on && same_besides_lag(*current.lag_searched_on, others)) return;
  const JointModel base = fit_joint_model(config, data, others, &current.model);
  if (!base.ok) return;
  const CandidateCause refit = extend_model(config, data, base, Cause::kInputLag, options);
  if (!refit.model.ok) return;
  // Judged as lambda is chosen: by val (the fine border model's lambda is chosen there).
  std::vector<double> simulated;
  const double fit = simulation_fit(refit.model, data, d.val_begin, d.val_end, &simulated);
  if (!(fit > current.fit)) return;
  current.model = refit.model;
  current.fit = fit;
  current.val_simulation = std::move(simulated);
  current.identification = residuals(current.model, data, false);
  end_last_step_here(d, current);  // the last step's gain includes the re-searched lambda
}

// Whether the nominal structure fitted by the colored_noise estimator (the evidence's candidate) simulates val more
// than coloured_backward_gain points better than the model found: its structural causes then only absorb the noise
// (the same test as drop_absorbing_structure's, for all of them at once). Where a lag absorbs sensor noise with a
// large lambda, its residuals can correlate less than coloured_correlation asks (tuning seeds 1086, 1193, 1236 of
// colored_noise: an input lag at lambda 0.71-0.80 simulating val at 56-69 %, the candidate at 86-91 %).
bool noise_simulates_better(const Diagnosis& d, const CurrentModel& current, const DiagnosisOptions& options) {
  if (!options.coloured_by_candidate || d.added.empty()) return false;
  const auto noise = std::find_if(d.candidates.begin(), d.candidates.end(),
                                  [](const CandidateCause& c) { return c.cause == Cause::kColoredNoise; });
  return noise != d.candidates.end() && noise->model.ok && far_better_on_val(noise->fit_val, current.fit, options);
}

}  // namespace

// Forward selection. Each round adds, among the supported structural candidates (every structural cause, and the
// other operator type), the one that simulates val best (the likelihood ratio alone prefers an input lag with its
// flexible borders over a true dead time), and refits the others on top of it. When no single one is supported,
// the two with the largest likelihood ratios are tried together, in both orders (an input lag and a drift can
// each look worse on val without the other); then the other operator type by its val error alone. Then
// colored_noise if the residuals are still not white (the extended model becomes the instrumental-variable fit of
// the structure found, if that simulates val as well).
void select_causes(Diagnosis& d, const ExperimentConfig& config, const FlatRecording& data,
                   const DiagnosisOptions& options) {
  CurrentModel current{d.nominal, d.fit_nominal, d.val_nominal, d.identification};
  // The val fit of `model`'s structure fitted by instrumental variables (the colored_noise extension).
  // The checks' IV fits: refitted by output error only with options.output_error_in_checks.
  DiagnosisOptions check_options = options;
  check_options.coloured_output_error = options.coloured_output_error && options.output_error_in_checks;
  const auto instrumental_val_fit = [&](const JointModel& model) {
    const CandidateCause iv = extend_model(config, data, model, Cause::kColoredNoise, check_options);
    return iv.model.ok ? simulation_fit(iv.model, data, d.val_begin, d.val_end) : -std::numeric_limits<double>::infinity();
  };
  const auto update_instrumental = [&]() { current.fit_instrumental = instrumental_val_fit(current.model); };
  if (options.instrumental_check) update_instrumental();
  std::vector<CandidateCause> round;
  for (const CandidateCause& c : d.candidates) {
    // Every structural cause stays a candidate, significant against the nominal model or not: a cause can be
    // invisible until another is modelled (a drift behind an unmodelled input lag: likelihood ratio 1 to 4 against
    // the nominal model on tuning seeds). structural_accepted tests each against the model built so far.
    if (c.model.ok && c.cause != Cause::kColoredNoise) {
      round.push_back(c);
    }
  }
  const auto refit = [&](Cause cause, const JointModel& base, const JointModel& before,
                         std::span<const double> before_val) {
    CandidateCause c = extend_model(config, data, base, cause, options);
    score_candidate(c, before, before_val, data, d.val_begin, d.val_end, options);
    return c;
  };
  // The candidate's own IV fit: for every structural candidate with options.instrumental_ranking, else only where
  // the IV check would otherwise reject it.
  const auto instrumental_fit = [&](CandidateCause& c) {
    if (!options.instrumental_check || !c.model.ok || c.cause == Cause::kOperatorType ||
        (!options.instrumental_ranking && c.fit_val > current.fit_instrumental) || !std::isnan(c.fit_instrumental)) {
      return;
    }
    c.fit_instrumental = instrumental_val_fit(c.model);
  };
  // Candidates are ranked by val, like with like where options.instrumental_ranking (under sensor noise a dead
  // time's least-squares val fit lost to an input lag's that absorbs the noise; its IV fit did not: tuning seeds
  // 1032 and 1036 of dead_time+colored_noise), a lag chosen on val less its optimism as in the IV check.
  const auto ranked = [&](const CandidateCause& c) {
    const double fit = options.instrumental_ranking ? best_fit(c.fit_val, c.fit_instrumental) : c.fit_val;
    return options.lag_optimism_in_ranking && lambda_chosen_on_val(c) ? fit - options.lag_val_optimism : fit;
  };
  // A drift on top of an input lag whose lambda was searched without it: if the drift is significant and explains
  // the residual correlation but the val checks reject it, lambda is searched again with the drift in (a drift
  // left out biases lambda, and the drift then simulates val worse with the old lambda).
  const auto research_lag = [&](CandidateCause& c) {
    if (!options.lag_with_drift || c.cause != Cause::kSensorDrift || !(current.model.structure.input_lag > 0) ||
        !c.model.ok || !detail::significant(c.likelihood_ratio, options) || structural_accepted(c, current, options)) {
      return;
    }
    const JointModel base =
        fit_joint_model(config, data, without_cause(c.model.structure, Cause::kInputLag), &c.model);
    if (!base.ok) return;
    CandidateCause lag = refit(Cause::kInputLag, base, current.model, current.val_simulation);
    if (!lag.model.ok || !(lag.model.structure.input_lag > 0)) return;
    lag.cause = Cause::kSensorDrift;
    lag.parameters = CauseParameters{};
    lag.parameters.drift_total = lag.model.drift_total();
    instrumental_fit(lag);
    if (structural_accepted(lag, current, options)) c = std::move(lag);
  };
  // The flipped-operator candidate among `candidates` if the current model supports it (operator_accepted), else end.
  const auto supported_flip = [&](const std::vector<CandidateCause>& candidates) {
    return std::find_if(candidates.begin(), candidates.end(), [&](const CandidateCause& c) {
      return c.cause == Cause::kOperatorType && operator_accepted(c, current, options);
    });
  };
  // The flipped operator before the round's best candidate, where that is an input lag with lambda near the top of
  // its range and a dead time on top of the flip simulates val far better (DiagnosisOptions::operator_first): with
  // the wrong operator, the cause the data hold can fit worse than a lag that absorbs the operator's error (a switch
  // configured as a backlash with a dead time took an input lag at lambda 0.73-0.8 first, and the dead time was
  // never found). A lambda pinned at its bound is the lag absorbing something; the generators hide lambda <= 0.5.
  const auto operator_first = [&](const std::vector<CandidateCause>& candidates,
                                  const CandidateCause& chosen) -> const CandidateCause* {
    if (chosen.cause != Cause::kInputLag ||
        !(chosen.model.structure.input_lag >= options.max_input_lag - kLambdaNearItsBound)) {
      return &chosen;
    }
    const auto flipped = supported_flip(candidates);
    if (flipped == candidates.end()) return &chosen;
    const bool delay_left = std::any_of(candidates.begin(), candidates.end(),
                                        [](const CandidateCause& c) { return c.cause == Cause::kDeadTime; });
    if (!delay_left) return &chosen;
    const CandidateCause delayed = refit(Cause::kDeadTime, flipped->model, current.model, current.val_simulation);
    return delayed.model.ok && far_better_on_val(delayed.fit_val, chosen.fit_val, options) ? &*flipped : &chosen;
  };
  while (!round.empty()) {
    on_two_threads(round.size(), [&](std::size_t i) { instrumental_fit(round[i]); });
    for (CandidateCause& c : round) research_lag(c);
    const CandidateCause* best = nullptr;
    for (const CandidateCause& c : round) {
      if (structural_accepted(c, current, options) && (best == nullptr || ranked(c) > ranked(*best))) best = &c;
    }
    if (best != nullptr && options.operator_first) best = operator_first(round, *best);
    std::vector<Cause> added;
    std::vector<const CandidateCause*> structural;
    for (const CandidateCause& c : round) {
      if (c.cause != Cause::kOperatorType && c.model.ok) structural.push_back(&c);
    }
    std::sort(structural.begin(), structural.end(),
              [](const auto* a, const auto* b) { return a->likelihood_ratio > b->likelihood_ratio; });
    if (best != nullptr) {
      added.push_back(best->cause);
      accept(d, current, *best, data);
    } else if (structural.size() >= 2) {
      // Both orders: a parameter searched without the other cause can be far off (an input lag's lambda, chosen
      // by val, without the drift that dominates val), and the second is searched on top of the first. The two
      // orders are independent: one on each thread, judged in order as a single thread would.
      const auto on_top = [&](const CandidateCause* a, const CandidateCause* b) {
        CandidateCause c = refit(b->cause, a->model, current.model, current.val_simulation);
        instrumental_fit(c);
        return c;
      };
      std::array<CandidateCause, 2> tried;
      on_two_threads(tried.size(), [&](std::size_t k) { tried[k] = on_top(structural[k], structural[1 - k]); });
      const CandidateCause* first = nullptr;
      CandidateCause both;
      for (std::size_t k = 0; k < tried.size(); ++k) {
        CandidateCause& c = tried[k];
        if (structural_accepted(c, current, options) && (first == nullptr || c.fit_val > both.fit_val)) {
          first = structural[k];
          both = std::move(c);
        }
      }
      if (first != nullptr) {
        added = {first->cause, both.cause};
        accept(d, current, *first, data);
        accept(d, current, both, data);
      }
    }
    if (added.empty()) {
      // Last: the other operator type by its val error alone (the identification phases cannot judge it).
      const auto flipped = supported_flip(round);
      if (flipped == round.end()) break;
      added.push_back(Cause::kOperatorType);
      accept(d, current, *flipped, data);
    }
    std::vector<Cause> remaining;
    for (const CandidateCause& c : round) {
      if (std::find(added.begin(), added.end(), c.cause) == added.end()) remaining.push_back(c.cause);
    }
    round = candidates_for(remaining, [&](Cause cause) {
      return refit(cause, current.model, current.model, current.val_simulation);
    });
    if (options.instrumental_check && !round.empty()) update_instrumental();
  }
  refine_input_lag(d, current, config, data, options);
  drop_unneeded_causes(d, current, config, data, options);
  const ResidualAnalysis& left = current.identification;
  ColoredNoiseCheck& check = d.colored_check;
  check.white = white(left, options);
  check.correlation = left.samples > 0 ? left.whiteness.statistic / static_cast<double>(left.samples) : 0.0;
  check.aperiodic_correlation = aperiodic_correlation(current.model, data, est::schedule::period(config.n, config.m));
  const double correlation = options.coloured_aperiodic ? check.aperiodic_correlation : check.correlation;
  if (!check.white && (correlation >= options.coloured_correlation || noise_simulates_better(d, current, options))) {
    CandidateCause iv = extend_model(config, data, current.model, Cause::kColoredNoise, options);
    // The cause is named by exclusion; its instrumental-variable model replaces the least-squares one only if it
    // was fitted (IV can find its instruments' matrix singular) and simulates val at least as well (an IV fit of a
    // large structure can be unstable).
    if (!iv.model.ok || simulation_fit(iv.model, data, d.val_begin, d.val_end) < current.fit) {
      iv.model = current.model;
      iv.parameters.instrumental_variables = false;
      iv.parameters.output_error = false;
    }
    accept(d, current, iv, data);
    drop_absorbing_causes(d, current, config, data, options);
    add_drift_beside_noise(d, current, config, data, options);
  }
  d.extended = current.model;
  d.fit_extended = current.fit;
  d.val_extended = current.val_simulation;
}

}  // namespace lashid::sim::detail
