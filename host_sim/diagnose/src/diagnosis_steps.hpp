// The model the forward selection builds (diagnosis_selection.cpp) and the steps that change it once the selection
// is done (diagnosis_steps.cpp): backward elimination, and the causes that only absorb a coloured disturbance.
#pragma once

#include <limits>
#include <optional>
#include <vector>

#include "diagnosis_candidates.hpp"

namespace lashid::sim::detail {

/// The model the selection has built so far, with the evidence the next step compares against.
struct CurrentModel {
  JointModel model;
  double fit = 0;
  std::vector<double> val_simulation;
  ResidualAnalysis identification;
  /// val fit of the same structure fitted by instrumental variables (-infinity when that fails or diverges).
  double fit_instrumental = -std::numeric_limits<double>::infinity();
  /// The structure the model's lambda was last searched on (CandidateCause::lag_searched_on).
  std::optional<ModelStructure> lag_searched_on = std::nullopt;
};

/// `model` becomes the current model, with its val simulation and identification residuals.
void adopt(CurrentModel& current, const JointModel& model, const Diagnosis& d, const FlatRecording& data);

/// The last step ends at the current model (after a change made once the selection is done), so that the steps
/// still add up to the total gain.
void end_last_step_here(Diagnosis& d, const CurrentModel& current);

/// Whether a val fit is more than DiagnosisOptions::coloured_backward_gain points above `than` (the current model's,
/// or a rival candidate's): the margin by which a model fitted by the colored_noise estimator replaces the one found,
/// once colored_noise is named or to name it (session 13's margin, used by every check of step 4 of the decision),
/// and by which the flip goes first (operator_first).
bool far_better_on_val(double fit, double than, const DiagnosisOptions& options);

/// The structure without `cause` (an input lag goes with its finer border tables; without an operator flip, the other
/// operator); the same structure for colored_noise and none.
ModelStructure without_cause(ModelStructure s, Cause cause);

/// Backward elimination once the forward selection is done: a structural cause that the final model no longer needs
/// (refitted without it, the others kept as they are, the likelihood ratio is not significant) is dropped.
void drop_unneeded_causes(Diagnosis& d, CurrentModel& current, const ExperimentConfig& config,
                          const FlatRecording& data, const DiagnosisOptions& options);

/// Once colored_noise is named: the structural causes (DiagnosisOptions::coloured_backward) and an operator flip
/// (DiagnosisOptions::coloured_operator_check) judged again by the colored_noise estimator, one at a time, then the
/// lags, dead times and flips left judged together (DiagnosisOptions::coloured_joint_drop); those that only
/// absorbed the disturbance are dropped.
void drop_absorbing_causes(Diagnosis& d, CurrentModel& current, const ExperimentConfig& config,
                           const FlatRecording& data, const DiagnosisOptions& options);

/// Once colored_noise is named and the absorbing causes are judged: a drift that the model lacks, judged again by the
/// colored_noise estimator (DiagnosisOptions::coloured_drift_check), and added, its step before colored_noise's, if
/// it simulates val far better.
void add_drift_beside_noise(Diagnosis& d, CurrentModel& current, const ExperimentConfig& config,
                            const FlatRecording& data, const DiagnosisOptions& options);

}  // namespace lashid::sim::detail
