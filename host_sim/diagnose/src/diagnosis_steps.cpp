// The current model's bookkeeping and the steps that change it once the forward selection is done
// (diagnosis_steps.hpp; docs/diagnose.md "Decision").
#include "diagnosis_steps.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <span>
#include <utility>
#include <vector>

namespace lashid::sim::detail {

void adopt(CurrentModel& current, const JointModel& model, const Diagnosis& d, const FlatRecording& data) {
  current.model = model;
  current.fit = simulation_fit(current.model, data, d.val_begin, d.val_end, &current.val_simulation);
  current.identification = residuals(current.model, data, false);
}

bool far_better_on_val(double fit, double than, const DiagnosisOptions& options) {
  return fit > than + options.coloured_backward_gain;
}

void end_last_step_here(Diagnosis& d, const CurrentModel& current) {
  if (d.added.empty()) return;
  d.added.back().fit_after = current.fit;
  d.added.back().ljung_box_after = current.identification.whiteness.statistic;
}

ModelStructure without_cause(ModelStructure s, Cause cause) {
  switch (cause) {
    case Cause::kSensorDrift:
      s.drift = false;
      break;
    case Cause::kDeadTime:
      s.delay = 0;
      break;
    case Cause::kInputLag:
      s.input_lag = 0;
      s.border_segments = 1;
      break;
    case Cause::kOperatorType:
      s.op = other_operator(s.op);
      break;
    case Cause::kColoredNoise:
    case Cause::kNone:
      break;
  }
  return s;
}

namespace {

// Whether `m` was fitted and simulates val far better than the current model (far_better_on_val): a model fitted by
// the colored_noise estimator then replaces the one found.
bool replaces_current(const JointModel& m, const Diagnosis& d, const CurrentModel& current, const FlatRecording& data,
                      const DiagnosisOptions& options) {
  return m.ok && far_better_on_val(simulation_fit(m, data, d.val_begin, d.val_end), current.fit, options);
}

// Removes step i; the step after it, if any, starts where the removed one did (its val fit and residual statistic
// before), so that the steps still add up from the nominal model.
void erase_step(Diagnosis& d, std::size_t i) {
  const AddedCause removed = d.added[i];
  d.added.erase(d.added.begin() + static_cast<std::ptrdiff_t>(i));
  if (i == d.added.size()) return;
  d.added[i].fit_before = removed.fit_before;
  d.added[i].ljung_box_before = removed.ljung_box_before;
}

// From the last added to the first, each structural cause for which `without(cause)` gives a model is dropped, and
// that model becomes the current one. The steps still add up to the total: the next step starts where the dropped
// one did, the last ends here. Returns how many were dropped.
template <class Without>
int drop_causes(Diagnosis& d, CurrentModel& current, const FlatRecording& data, Without without) {
  int count = 0;
  for (std::size_t i = d.added.size(); i-- > 0;) {
    const Cause cause = d.added[i].cause;
    if (cause != Cause::kSensorDrift && cause != Cause::kDeadTime && cause != Cause::kInputLag) continue;
    const std::optional<JointModel> reduced = without(cause);
    if (!reduced) continue;
    erase_step(d, i);
    adopt(current, *reduced, d, data);
    end_last_step_here(d, current);
    ++count;
  }
  return count;
}

// colored_noise's model is now the colored_noise estimator's fit (after a cause was dropped for it).
void colored_noise_model_is_current(Diagnosis& d, const CurrentModel& current) {
  for (AddedCause& a : d.added) {
    if (a.cause != Cause::kColoredNoise) continue;
    a.parameters.instrumental_variables = true;
    a.parameters.output_error = current.model.structure.output_error;
  }
}

// The output-error criterion of a colored_noise fit (its simulation error on the identification phases); infinity
// where output error could not refine it.
double criterion(const JointModel& m) {
  return std::isnan(m.simulation_sse) ? std::numeric_limits<double>::infinity() : m.simulation_sse;
}

// Once colored_noise is named, the structural causes are judged again by the estimator that a coloured
// disturbance calls for. Under sensor noise least squares accepts extensions that only absorb the noise (their
// likelihood ratio is not valid then), and the val and IV checks let some through: an input lag or a dead time
// beside the noise of order-3 plants (tuning seeds 1195, 1201, 1222, 1227 of colored_noise; 1194, 1079 and 1104 of
// the pairs with it). A cause is dropped when the structure without it, fitted by the colored_noise estimator (IV,
// then output error), simulates val more than options.coloured_backward_gain points better than the model found.
// A margin, not any gain: true dead times beside sensor noise lost 0.3 to 0.6 points on val to their removal
// (pairs 1078, 1125: hits that a margin of 0 lost), the noise-absorbing causes 9.6 to 40.8. The structure without
// an input lag or a dead time is fitted from the current model and from no start, the lower output-error criterion
// kept (session 33; test seed 12408 of colored_noise: from the lag model's regimes it simulated val at 35.6 %, from
// none at 84.1 %, where the model found had 56.4 %).
void drop_absorbing_structure(Diagnosis& d, CurrentModel& current, const ExperimentConfig& config,
                              const FlatRecording& data, const DiagnosisOptions& options) {
  if (!options.coloured_backward) return;
  const int dropped = drop_causes(d, current, data, [&](Cause cause) -> std::optional<JointModel> {
    const ModelStructure s = coloured_estimator(without_cause(current.model.structure, cause), options);
    JointModel reduced = fit_joint_model(config, data, s, &current.model);
    if (cause != Cause::kSensorDrift) {
      // Without a lag or a dead time the operator sees another input, on which the current model's regimes can be a
      // poor start: also fitted from none, and the lower output-error criterion kept.
      JointModel fresh = fit_joint_model(config, data, s);
      if (fresh.ok && (!reduced.ok || criterion(fresh) < criterion(reduced))) reduced = std::move(fresh);
    }
    if (!replaces_current(reduced, d, current, data, options)) return std::nullopt;
    return reduced;
  });
  if (dropped > 0) colored_noise_model_is_current(d, current);
}

// An operator flip accepted by least squares is judged again, once colored_noise is named, by the same test with the
// colored_noise estimator: the structure with the operator flipped back is fitted by it (no start: the regimes of
// the other operator do not apply), and the flip stays only if the model found brings the val error energy below
// operator_sse_ratio of that fit's. Under sensor noise the flipped least-squares model can simulate val better by
// absorbing the noise: on the tuning seeds 1040-1239 (session 32) 10 pairs named a flip beside colored_noise where
// none was hidden; with this check 8 of them are right (dead_time+colored_noise 1046, 1120: val fit 74.6 and 75.8 %
// with the flip, 93.0 and 87.4 % without it), and no single cause changed.
void drop_absorbing_flip(Diagnosis& d, CurrentModel& current, const ExperimentConfig& config,
                         const FlatRecording& data, const DiagnosisOptions& options) {
  if (!options.coloured_operator_check) return;
  const auto flip = std::find_if(d.added.begin(), d.added.end(),
                                 [](const AddedCause& a) { return a.cause == Cause::kOperatorType; });
  if (flip == d.added.end()) return;
  const JointModel back =
      fit_joint_model(config, data, coloured_estimator(without_cause(current.model.structure, flip->cause), options));
  if (!back.ok) return;
  std::vector<double> simulated;
  // A flipped-back fit whose val simulation diverges cannot judge the flip: it stays.
  if (!std::isfinite(simulation_fit(back, data, d.val_begin, d.val_end, &simulated))) return;
  const std::span<const double> measured(data.y.data() + d.val_begin, d.val_end - d.val_begin);
  if (flip_error_ratio(simulated, current.val_simulation, measured) < options.operator_sse_ratio) return;
  erase_step(d, static_cast<std::size_t>(flip - d.added.begin()));
  adopt(current, back, d, data);
  end_last_step_here(d, current);
  colored_noise_model_is_current(d, current);
}

// The causes left beside colored_noise judged together: each of an input lag and an operator flip can pass its own
// check because the other one is still there (tuning seed 1236 of colored_noise: a switch with lambda 0.80 simulating
// val at 56 %, the nominal backlash fitted by the colored_noise estimator at about 86 %). The structure without every
// lag, dead time and flip (a drift stays: it is no noise absorber), fitted by the colored_noise estimator from no
// start, replaces the model if it simulates val more than options.coloured_backward_gain points better.
void drop_absorbing_together(Diagnosis& d, CurrentModel& current, const ExperimentConfig& config,
                             const FlatRecording& data, const DiagnosisOptions& options) {
  if (!options.coloured_joint_drop) return;
  const auto absorbing = [](const AddedCause& a) {
    return a.cause == Cause::kInputLag || a.cause == Cause::kDeadTime || a.cause == Cause::kOperatorType;
  };
  if (std::count_if(d.added.begin(), d.added.end(), absorbing) < 2) return;
  ModelStructure s = current.model.structure;
  for (const AddedCause& a : d.added) {
    if (absorbing(a)) s = without_cause(s, a.cause);
  }
  const JointModel reduced = fit_joint_model(config, data, coloured_estimator(s, options));
  if (!replaces_current(reduced, d, current, data, options)) return;
  for (std::size_t i = d.added.size(); i-- > 0;) {
    if (absorbing(d.added[i])) erase_step(d, i);
  }
  adopt(current, reduced, d, data);
  end_last_step_here(d, current);
  colored_noise_model_is_current(d, current);
}

}  // namespace

// Backward elimination (diagnosis_steps.hpp).
// The two-causes fallback adds a pair whose first member is not tested alone: on curved borders a drift of
// nothing came in with an input lag (a drift_total of 1e-4 to 0.05 where none was hidden).
void drop_unneeded_causes(Diagnosis& d, CurrentModel& current, const ExperimentConfig& config,
                          const FlatRecording& data, const DiagnosisOptions& options) {
  if (!options.backward_elimination) return;
  drop_causes(d, current, data, [&](Cause cause) -> std::optional<JointModel> {
    JointModel reduced =
        fit_joint_model(config, data, without_cause(current.model.structure, cause), &current.model);
    if (!reduced.ok || detail::significant(detail::likelihood_ratio(reduced, current.model), options)) {
      return std::nullopt;
    }
    return reduced;
  });
}

// Once colored_noise is named, a drift that least squares refused is judged again by the colored_noise estimator:
// under sensor noise its likelihood ratio is not valid, and its least-squares fit can simulate val no better than
// the model without it. On the pairs of the tuning seeds 1040-1239 where a hidden drift was missed for colored_noise
// (sensor_drift+colored_noise 1044, 1070, 1116, 1184, 1212, ...), the true structure fitted by that estimator
// simulates val at 87 to 94 %, the model found at 41 to 81 %. The drift is added if the structure with it, fitted by
// that estimator, simulates val more than options.coloured_backward_gain points better. It is a structural cause,
// so its step goes before colored_noise's, which is named by exclusion: the drift's step runs from where the noise's
// began to the model with the drift (the estimator's change included), and the noise's step then changes nothing.
// Its likelihood ratio is 0, as the noise's: the one-step residuals of output-error fits do not give a valid one.
void add_drift_beside_noise(Diagnosis& d, CurrentModel& current, const ExperimentConfig& config,
                            const FlatRecording& data, const DiagnosisOptions& options) {
  if (!options.coloured_drift_check || current.model.structure.drift) return;
  const auto noise = std::find_if(d.added.begin(), d.added.end(),
                                  [](const AddedCause& a) { return a.cause == Cause::kColoredNoise; });
  if (noise == d.added.end()) return;
  ModelStructure s = current.model.structure;
  s.drift = true;
  const JointModel with = fit_joint_model(config, data, coloured_estimator(s, options), &current.model);
  if (!replaces_current(with, d, current, data, options)) return;
  AddedCause drift;
  drift.cause = Cause::kSensorDrift;
  drift.fit_before = noise->fit_before;
  drift.ljung_box_before = noise->ljung_box_before;
  adopt(current, with, d, data);
  drift.fit_after = noise->fit_before = noise->fit_after = current.fit;
  drift.ljung_box_after = noise->ljung_box_before = noise->ljung_box_after = current.identification.whiteness.statistic;
  d.added.insert(noise, drift);
  colored_noise_model_is_current(d, current);
}

void drop_absorbing_causes(Diagnosis& d, CurrentModel& current, const ExperimentConfig& config,
                           const FlatRecording& data, const DiagnosisOptions& options) {
  drop_absorbing_structure(d, current, config, data, options);
  drop_absorbing_flip(d, current, config, data, options);
  drop_absorbing_together(d, current, config, data, options);
}

}  // namespace lashid::sim::detail
