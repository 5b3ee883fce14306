// diagnose-sweep --oracle (docs/diagnose-history.md, "Where a backlash's lambda is lost"): the generator's own plant
// put on a fitted model's border tables, to tell whether a miss comes from the model class (the truth fits no better
// than the fit) or from the estimator (the truth, in the same class, fits far better than the estimate).
#pragma once

#include <optional>

#include <nlohmann/json.hpp>

#include "lashid/analysis/joint_model.hpp"
#include "lashid/sim/hidden_effect.hpp"

namespace lashid::app {

/// Squared one-step errors as multiples of rows x the generator's equation-error variance (1 for the true plant
/// with its exact borders), and val fits (%).
struct OracleCheck {
  double truth = 0;              ///< the true plant on the fit's tables (self-consistent: its own regimes)
  double fit_rss = 0;            ///< the fit's regression error, with the regimes it was fitted with
  double fit_consistent = 0;     ///< the fit's own one-step error, with the regimes its borders give
  /// The same structure fitted again (fit_joint_model's regime iteration) with the truth's regimes as its only
  /// start: its regression error, and its own one-step error.
  double from_true_regimes_rss = 0;
  double from_true_regimes = 0;
  /// The same, with ModelStructure::regime_consistency: its own one-step error and val fit.
  double from_true_regimes_consistent = 0;
  /// The same structure fitted with ModelStructure::regime_search (from the usual starts, no truth used): its own
  /// one-step error and val fit.
  double regime_search = 0;
  double val_truth = 0, val_fit = 0, val_from_true_regimes = 0, val_from_true_regimes_consistent = 0;
  double val_regime_search = 0;
};

/// The check for `fit`, the true structure `structure` fitted to `data` (the flat recording of `c`). nullopt where
/// the equation error is not the only disturbance (sensor_drift, colored_noise hidden) or the fit failed.
std::optional<OracleCheck> oracle_check(const sim::HiddenEffectCase& c, const sim::FlatRecording& data,
                                        const sim::ModelStructure& structure, const sim::JointModel& fit);

nlohmann::json to_json(const std::optional<OracleCheck>& check);

}  // namespace lashid::app
