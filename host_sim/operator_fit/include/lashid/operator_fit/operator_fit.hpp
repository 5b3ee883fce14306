// Fitting the paper's operators (switch (2.3), backlash (2.4)) and the friction-gap extension to measured
// input/output records u = F[v] (docs/friction-damper.md), simulating them, and locating their error on the loop.
#pragma once

#include <array>
#include <cstddef>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "lashid/io/damper_data.hpp"
#include "lashid/plant/border.hpp"
#include "lashid/plant/friction_gap.hpp"
#include "lashid/plant/operators.hpp"

namespace lashid::sim {

struct OperatorFitOptions {
  int points = 41;          ///< nodes of every fitted table (borders over the training range of v; G over the play)
  double deadband = 0.002;  ///< a reversal is declared when v retreats this far from its running extreme
  /// Candidate half-widths r of the play [-r, r]; the one with the least training error is kept. Empty: 0.02 to
  /// 0.50 by 0.02.
  std::vector<double> half_widths;
  bool parallel_stiffness = true;  ///< fit k of u = G(v - z) + k v (false: k = 0)
};

/// Direction of motion (+1 up, -1 down) at every sample, with hysteresis: the direction changes only once v has
/// moved `deadband` back from its extreme since the last change, so measurement noise of a few LSB is not motion.
/// Samples before the first decision take the first decided direction (+1 if v never moves that far).
std::vector<int> motion_direction(std::span<const double> v, double deadband);
/// Indices of the extremes where the direction of motion_direction() changes (the reversal points).
std::vector<std::size_t> reversal_indices(std::span<const double> v, double deadband);

/// Nonparametric border on [lo, hi]: `points` equally spaced nodes, each the median (stats::median) of the u of the
/// samples (v, u) nearest to it; nodes without samples are left out (linear interpolation between their neighbours).
/// Throws std::invalid_argument for points < 2, lo >= hi or fewer than 2 nodes with samples.
Border fit_border(std::span<const std::pair<double, double>> samples, double lo, double hi, int points);

/// The operator run on a record's input from the record's first sample: reset(v[0], u[0]), then step(v[t]).
/// The first output is the measured u[0]; the operator is cloned, `op` is not changed.
std::vector<double> simulate_operator(const HysteresisOperator& op, std::span<const double> v, double u0);
/// Fit (%) of a simulated force to the record's measured force, stats::fit_percent(record.u, u_sim). A simulation
/// with a non-finite sample scores -inf: a diverged model is the worst model, not an error (as in diagnose). Throws
/// std::invalid_argument naming record.source when the record cannot be scored (sizes differ, fewer than 2
/// samples, constant force).
double fit_to_record(const DamperRecord& record, std::span<const double> u_sim);

struct NominalFit {
  Border ascending;   ///< median of u over rising samples, by v
  Border descending;  ///< same over falling samples
  double fit_train_switch = 0;    ///< mean training fit (%) of the switch with these borders
  double fit_train_backlash = 0;  ///< same for the backlash
  std::string chosen;             ///< "switch" or "backlash": the better mean training fit
  std::unique_ptr<HysteresisOperator> make() const;  ///< the chosen operator
};
/// Borders from all training samples (direction from motion_direction()), both operators simulated on every
/// training file, the better kept. Throws std::invalid_argument for no training data.
NominalFit fit_nominal(const std::vector<DamperRecord>& train, const OperatorFitOptions& options);

struct ExtendedFit {
  double half_width = 0;  ///< r of the play [-r, r]
  double stiffness = 0;   ///< k
  std::vector<std::pair<double, double>> curve;  ///< G as a table (e, u)
  double fit_train = 0;   ///< mean training fit (%)
  std::vector<std::pair<double, double>> train_error_by_width;  ///< (r, training RMS error) of every candidate
  std::unique_ptr<FrictionGapOperator> make() const;
};
/// For each candidate r: the relative displacement e(t) of a play started mid-play, G = per-node medians of u - k v
/// against e, k by least squares of u - G(e) against v (alternated 3 times); the r of least training squared error
/// is kept. Training files only. Throws std::invalid_argument for no training data.
ExtendedFit fit_extended(const std::vector<DamperRecord>& train, const OperatorFitOptions& options);

/// G and k of the friction-gap operator for one play half-width r (the inner step of fit_extended()): the play's
/// offsets e(t) started mid-play, G = per-node medians of u - k v against e on `options.points` nodes of [-r, r], k
/// by least squares (alternated 3 times). Throws std::invalid_argument for no records or r <= 0.
struct CurveAtWidth {
  std::vector<std::pair<double, double>> curve;  ///< G as a table (e, u)
  double stiffness = 0;                          ///< k
  double squared_error = 0;                      ///< sum over the records of (u - G(e) - k v)^2
  std::size_t samples = 0;
};
CurveAtWidth fit_curve_at_width(const std::vector<DamperRecord>& records, double width,
                                const OperatorFitOptions& options);
/// options.half_widths, or 0.02 to 0.50 by 0.02 when it is empty.
std::vector<double> candidate_half_widths(const OperatorFitOptions& options);
/// The search of fit_extended() without its training fit: for each candidate_half_widths() r, fit_curve_at_width();
/// the r of least training squared error (the first of equal ones) with its G and k, and every candidate's RMS
/// error. fit_train is left 0. Shared by fit_extended() and the per-tension fit (band_tension.hpp).
ExtendedFit best_half_width(const std::vector<DamperRecord>& records, const OperatorFitOptions& options);

// --------------------------------------------------------------------------------- error by phase of the loop

struct LoopPhaseOptions {
  double deadband = 0.002;           ///< reversal detection, as in motion_direction()
  double reversal_window = 0.05;     ///< "reversal": travel since the last reversal below this
  double engagement_window = 0.30;   ///< "gap/engagement": travel in [reversal_window, this); beyond: "sliding"
  double stick_speed = 0.02;         ///< "stick": |dv/dt| below this (units of v per second), outside reversals
};

/// The phases of the loop, in the order of LoopAnalysis::phases.
enum class LoopPhase : std::size_t { kReversal, kEngagement, kSliding, kStick };
/// Their names, as in PhaseError::phase and the JSON report.
inline constexpr std::array<const char*, 4> kLoopPhaseNames{"reversal", "engagement", "sliding", "stick"};

struct PhaseError {
  std::string phase;  ///< kLoopPhaseNames: reversal, engagement, sliding, stick
  std::size_t samples = 0;
  double share_of_squared_error = 0;  ///< fraction of the file's sum of squared errors
  double rms = 0;                     ///< RMS error within the phase
};

struct LoopAnalysis {
  std::vector<PhaseError> phases;  ///< one per LoopPhase, in its order
  std::size_t reversals = 0;
  double plateau = 0;                  ///< friction level: 90 % quantile of |u| measured
  double measured_reversal_slope = 0;  ///< median |du/dv| over the first reversal_window of travel after reversals
  double simulated_reversal_slope = 0;
  double measured_gap = 0;   ///< median travel per half-cycle with |u| < 0.1 plateau (half-cycles of full travel)
  double simulated_gap = 0;
  double measured_gap_centre_spread = 0;  ///< max - min over those half-cycles of the gap's mean position
  double peak_speed = 0;                  ///< 95 % quantile of |dv/dt| (50 ms centred differences)

  const PhaseError& phase(LoopPhase p) const { return phases.at(static_cast<std::size_t>(p)); }
};

/// Splits the squared error u - u_sim of a record by phase of the loop and measures the reversal slope and the
/// zero-force gap of the measurement and of the simulation.
LoopAnalysis analyse_loop(const DamperRecord& record, std::span<const double> u_sim, const LoopPhaseOptions& options);

}  // namespace lashid::sim
