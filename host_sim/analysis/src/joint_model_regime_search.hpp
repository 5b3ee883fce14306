// Regime search of a backlash fit (ModelStructure::regime_search; docs/diagnose-history.md, "Where a backlash's lambda
// is lost").
//
// The regime iteration (fit_joint_model) refits from the regimes the last fit's borders give and stops once the
// regression error no longer falls. It can end where least squares fits the data well with regimes that the
// model's own backlash does not take: its own one-step error (self_consistent_rss) is then many times the noise
// (session 11 measured 25 of 59 backlash fits at the true input lag above 3 times it). In the pulse experiments
// (3.1)/(4.2) the input repeats with the period T of (3.25), so once the first periods have passed the regimes form
// a pattern of T labels per experiment: move down (C_d), hold, move up (C_a). The search changes one label of that
// pattern at a time (a hold becomes a move in w's direction, a move becomes a hold), in every period from the third
// on where the input repeats, refits for the new regimes, and keeps the change that lowers the model's own error
// the most; it ends when no change lowers it by a relative kRegimeSearchGain, or after kRegimeSearchRounds changes.
// Its cost is about 2T fits per round.
#pragma once

#include <functional>
#include <vector>

#include "joint_model_layout.hpp"
#include "lashid/analysis/joint_model.hpp"

namespace lashid::sim::detail {

/// Changes of the regime pattern at most.
inline constexpr int kRegimeSearchRounds = 8;
/// A change is kept only if it lowers the own one-step error by at least this fraction.
inline constexpr double kRegimeSearchGain = 1e-3;

/// The least-squares fit for given regimes, warm-started from a model with the same tables.
using FitForRegimes = std::function<JointModel(const Basis& phi, const JointModel& warm)>;

struct RegimeSearch {
  JointModel model;
  Basis phi;
  int changes = 0;  ///< labels of the periodic pattern changed
};

/// The search from `model`, fitted for the regimes `phi` of input w; `fit` refits for other regimes. Returns
/// `model` and `phi` unchanged when no change of the pattern lowers the own error (or the recording has no pulse
/// phase of three periods).
RegimeSearch search_regimes(const ExperimentConfig& config, const Layout& layout, const FlatRecording& data,
                            const std::vector<double>& w, JointModel model, Basis phi, const FitForRegimes& fit);

}  // namespace lashid::sim::detail
