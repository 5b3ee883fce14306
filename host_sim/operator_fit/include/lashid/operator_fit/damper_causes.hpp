// Causes of a nominal operator's error on measured damper data, named from the loop analyses of the test files
// (docs/friction-damper.md, "Causes that the command names").
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "lashid/operator_fit/operator_fit.hpp"
#include "lashid/operator_fit/output_dynamics.hpp"

namespace lashid::sim {

struct DamperCause {
  std::string name;                ///< e.g. finite_stiffness_at_reversal
  bool in_extended_model = false;  ///< whether the friction_gap operator models it
  std::string evidence;            ///< one sentence with the numbers that support it
};

/// The thresholds of the rules in damper_causes(). The defaults are those of `lashid operator-fit`.
struct DamperCauseOptions {
  /// finite_stiffness_at_reversal: mean share of the nominal squared error in the reversal and engagement phases
  /// above which most of the error follows a reversal.
  double reversal_error_share = 0.5;
  /// zero_force_gap_moving_with_reversal: mean measured travel per half-cycle with |u| below 10 % of the friction
  /// level (units of v) above which there is a gap at all; it must also move more than its width.
  double min_gap = 0.02;
  /// position_dependent_friction: fraction of the friction level by which the fitted parallel stiffness must change
  /// the force over the training range of v to count.
  double stiffness_force_share = 0.05;
  /// rate_dependence: the extended model's RMS error while sliding on the fastest test file (by peak speed) must
  /// exceed this multiple of that on the slowest.
  double sliding_rms_ratio = 1.5;
  /// dynamics_after_friction_element: fraction of the extended operator's squared error on the test files that the
  /// filter after it (identified on the training files) must remove to count.
  double dynamics_error_reduction = 0.10;
  /// friction_level_scales_with_band_tension: fraction of the tension-blind extended operator's squared error on
  /// the test files that the operator fitted per band tension must remove to count.
  double band_tension_error_reduction = 0.10;
};

/// The extended operator's squared error on the test files without and with the filter after it (sums over the
/// files), and its mean test fit (%) without and with.
struct TestErrors {
  double extended = 0;
  double with_dynamics = 0;
  double mean_fit_extended = 0;
  double mean_fit_dynamics = 0;
};

/// Causes supported by the errors on the test files, in this order when present: finite_stiffness_at_reversal,
/// zero_force_gap_moving_with_reversal, position_dependent_friction (from `nominal`, averaged over the files, and
/// `extended_fit`), rate_dependence (from `extended`; the operators are rate-independent, so it is not in the
/// extended model). `nominal` and `extended` are the analyses of the nominal and the extended model, one per test
/// file; `v_span` is the training range of v. No test files: no causes.
std::vector<DamperCause> damper_causes(const std::vector<LoopAnalysis>& nominal,
                                       const std::vector<LoopAnalysis>& extended, const ExtendedFit& extended_fit,
                                       double v_span, const DamperCauseOptions& options = {});

/// One sentence on the filter after the extended operator, whatever its gain: its dominant pole (dominant_pole())
/// in words (ringing frequency and damping zeta when it oscillates, time constant when it is real) and how much of
/// the extended operator's squared error on the test files it removes (or adds).
std::string output_dynamics_in_words(const std::vector<FilterPole>& poles, int order, const TestErrors& errors);

/// dynamics_after_friction_element: named when the filter B(q)/A(q) after the extended operator (identified on the
/// training files; `poles` from filter_poles(), `order` its order) removes at least
/// options.dynamics_error_reduction of the extended operator's squared error on the test files; the evidence is
/// output_dynamics_in_words(). No poles or too little gain: nothing.
std::optional<DamperCause> dynamics_after_friction_element(const std::vector<FilterPole>& poles, int order,
                                                           const TestErrors& errors,
                                                           const DamperCauseOptions& options = {});

}  // namespace lashid::sim
