// The pieces of the diagnosis shared by the decision (diagnosis.cpp) and the candidate fits
// (diagnosis_candidates.cpp): one model extended by one more cause, and the evidence scored on it.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "lashid/diagnose/diagnosis.hpp"

namespace lashid::sim::detail {

/// The val phase of the flattened recording: [first val sample, last val sample + 1); {0, 0} without one.
std::pair<std::size_t, std::size_t> val_range(const FlatRecording& data);

/// N ln(RSS_before / RSS_after) on the identification rows (0 when `after` failed).
double likelihood_ratio(const JointModel& before, const JointModel& after);

/// Whether a structural extension with this likelihood ratio (one parameter) is significant at
/// options.structural_p.
bool significant(double likelihood_ratio, const DiagnosisOptions& options);

/// Correlation analysis of the one-step residuals of `model` on the identification phases, or on val.
ResidualAnalysis residuals(const JointModel& model, const FlatRecording& data, bool validation);
/// Ljung-Box Q / N of the model's identification residuals without their periodic part
/// (ColoredNoiseCheck::aperiodic_correlation); `period` is the pulse period T of the design.
double aperiodic_correlation(const JointModel& model, const FlatRecording& data, int period);

double sse(std::span<const double> a, std::span<const double> b);

/// `s` fitted by the estimator a coloured disturbance calls for (colored_noise's): instrumental variables, then output
/// error where options.coloured_output_error.
ModelStructure coloured_estimator(ModelStructure s, const DiagnosisOptions& options);

/// The test statistic of a flipped operator (DiagnosisOptions::operator_sse_ratio): the val error energy of the model
/// with it (`after_val`, simulated) over that of the model before it; against a model whose val simulation
/// diverges, 0 if the flipped one's does not, infinity if it does too.
double flip_error_ratio(std::span<const double> before_val, std::span<const double> after_val,
                        std::span<const double> measured);

/// `current` extended by an input lag: lambda over its range, with borders linear between the levels or finer
/// (input_lag_search.cpp).
JointModel search_input_lag(const ExperimentConfig& config, const FlatRecording& data, const JointModel& current,
                            const DiagnosisOptions& options);

/// `current` extended by `cause` (its parameter searched: lambda over a grid, by RSS with borders linear between
/// the levels or by val with finer borders, see search_input_lag; the delay over 1..max_delay), fitted on the
/// identification phases. Lambda is searched over its whole range in every round: a lag searched on top of a drift
/// only near the first round's value (fitted without the drift) missed it by up to 0.4 (tuning seeds 1007 and 1019
/// of input_lag+sensor_drift).
CandidateCause extend_model(const ExperimentConfig& config, const FlatRecording& data, const JointModel& current,
                            Cause cause, const DiagnosisOptions& options);

/// The evidence on a candidate against the model it extends: val fit, residual analysis, likelihood ratio, and
/// the statistic the report shows (the val error ratio for the operator type, which the identification phases
/// usually cannot judge).
void score_candidate(CandidateCause& candidate, const JointModel& before, std::span<const double> before_val,
                     const FlatRecording& data, std::size_t val_begin, std::size_t val_end,
                     const DiagnosisOptions& options);

/// One candidate per cause, in order, made by `make`, each on its own thread (a candidate only reads the data and
/// the model it extends; the input lag's search costs about as much as all the others together). The answers do
/// not depend on it.
std::vector<CandidateCause> candidates_for(const std::vector<Cause>& causes,
                                           const std::function<CandidateCause(Cause)>& make);

}  // namespace lashid::sim::detail
