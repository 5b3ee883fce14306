// One consistent model of the whole plant from both identification experiments, and its candidate extensions.
//
// The DIS and the AIS each give a linear part and one border (Sections 3 and 4). `lashid diagnose` needs a single
// model it can simulate on arbitrary inputs, and the same fit with one physical effect added. Both come from the
// regression (3.19) written for all identification phases at once (step_d, dis, step_a, ais, in recording order):
//
//   y(t) = -sum_i a_i y(t-i) + sum_i b_i u~(t-i) + kappa0 [+ kappa1 tau(t)] + e(t),    u~ = F[w] - u_M,
//
// where u~(t) = phi(t)' c is linear in the border values c: phi(t) holds the interpolation (hat) weights of w(t)
// on the border the operator moves along at t, or phi(t-1) when it holds. The border points are the experiment's
// own abscissas: C_d on V_d and v_max, C_a on V_a and v_min, with C_d(v_max) = C_a(v_max) = u_M (the reference,
// u~ = 0) and C_a(v_min) = C_d(v_min) = u_m. Unknowns: a, the n x (2m-1) products b_i c_k (the paper's
// over-parametrisation, (3.21)), kappa0 = B(1) u_M [+ A(1) offset], and, with drift, kappa1. Least squares (or
// instrumental variables) gives them; b and c are recovered by the best rank-1 factorisation, scaled as (3.11c):
// C~_d(v_min) = u_m - u_M = -1. With finer border tables (border_segments > 1) and n >= 2, least squares is
// then restricted to rank one (Gauss-Newton steps, joint_model_solve.cpp): there the unrestricted products amount
// to n free borders, and their fit says little about the rank-1 model that is simulated. With a white equation
// error and the nominal structure this is the same estimator as the paper's; the extensions change w (input lag,
// dead time), add a regressor (drift) or the estimator (IV).
#pragma once

#include <cstddef>
#include <limits>
#include <string>
#include <vector>

#include "lashid/io/config.hpp"
#include "lashid/io/recording.hpp"
#include "lashid/plant/border.hpp"

namespace lashid::sim {

/// The recording flattened in recording order; tau is the sample index from the first sample of the file.
struct FlatRecording {
  std::vector<double> v, y;
  std::vector<Phase> phase;
  std::size_t size() const { return v.size(); }
  bool is_identification(std::size_t t) const { return phase[t] != Phase::kVal; }
};
FlatRecording flatten(const Recording& recording);

/// What the model contains besides the nominal plant.
struct ModelStructure {
  OperatorKind op = OperatorKind::kBacklash;
  double input_lag = 0;       ///< lambda of G = (1-lambda)/(1-lambda q^-1) before the operator (Section 3.5.3)
  int delay = 0;              ///< extra pure delay d between command and effect
  bool drift = false;         ///< y carries an offset that changes linearly over the recording
  bool instrumental = false;  ///< instrumental variables instead of least squares (disturbance not white)
  /// With instrumental: a_i, b_i, the border values and the offsets then refitted by output error (the simulation
  /// error on the identification phases), where the borders are the experiment's abscissas (border_segments 1).
  bool output_error = false;
  /// With output_error: output error is also started from the least-squares model and, where the IV model's A is
  /// unstable, from the IV model with A's unstable roots reflected into the unit circle; the start that ends with
  /// the lowest simulation error on the identification phases (the criterion) is kept. Off: from the IV model only.
  bool output_error_restarts = true;
  /// Segments per interval between the experiment's abscissas in the border tables (1: the abscissas only). More
  /// segments only matter where the operator's input moves between the levels (an input lag): there a real
  /// border's curvature between the levels would otherwise bias lambda. Points the data never reach are
  /// interpolated from their neighbours.
  int border_segments = 1;
  /// Weight, in samples, of the prior that a point between the abscissas lies on the line through its neighbours.
  double border_smoothness = 20.0;
  /// Backlash with the finer tables (border_segments > 1) only: C~_a <= C~_d at every table point, the backlash's
  /// play non-negative. Where the fitted borders cross beside the end points, where they meet, a lagged input
  /// that never reaches the end exactly leaves the model's backlash holding for good (docs/diagnose.md). Off: the
  /// borders as fitted, crossing allowed (the paper's class, which the nominal model keeps). `rss` and `residuals`
  /// stay the regression's, from the borders before the play is made non-negative.
  bool non_negative_play = true;
  /// Backlash only: every least-squares fit is held to the regimes it is fitted with (penalty rows on the borders
  /// where the model's own backlash would move or hold otherwise, joint_model_consistency.hpp), and a fit that
  /// takes its own regimes ends the regime iteration. Off in the diagnosis: on the tuning seeds it made the
  /// fits from the true regimes consistent but the diagnosis worse and 4 times slower (docs/diagnose-history.md).
  bool regime_consistency = false;
  /// Backlash only: after the regime iteration, a search over the pulse experiments' periodic regime pattern,
  /// judged by the model's own one-step error (joint_model_regime_search.hpp). About 2T fits per change, T the
  /// pulse period. Off in the diagnosis: on the tuning seeds it cut the true-lag fits' own error but not the
  /// misses, at several times the cost (docs/diagnose-history.md); `diagnose-sweep --oracle` reports it.
  bool regime_search = false;
};

/// A fitted model, in the scaling of (3.11c) (u~ = F - u_M, C~_d(v_min) = -1).
struct JointModel {
  ModelStructure structure;
  int n = 0;
  double v_min = 0, v_max = 0;
  std::vector<double> a, b;
  std::vector<double> descending_v, descending_u;  ///< C~_d table: V_d, then v_max (u~ = 0), and points in between
  std::vector<double> ascending_v, ascending_u;    ///< C~_a table: v_min (u~ = C~_d(v_min)), V_a ascending, and between
  double kappa0 = 0;            ///< constant of the equation: B(1) u_M + A(1) * offset
  double kappa1 = 0;            ///< coefficient of tau / (samples - 1): A(1) * (offset change over the file)
  double residual_variance = 0; ///< RSS / (rows - parameters) of the fit
  double rss = 0;
  std::size_t rows = 0;
  int parameters = 0;
  double rank_one_ratio = 0;    ///< sigma_2 / sigma_1 of the b c' products (0 = exactly rank one)
  /// structure.output_error: the criterion output error minimised, the simulation error energy on the
  /// identification phases (each simulated from its measured start); NaN otherwise.
  double simulation_sse = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> residuals;         ///< of the regression, on the identification rows
  std::vector<std::size_t> residual_t;   ///< sample index of each residual
  bool ok = false;              ///< false: the regression was singular or the factorisation degenerate
  std::string failure;          ///< why, when !ok

  double a_sum() const;  ///< A(1)
  /// Offset change from the first to the last sample of the recording (sensor_drift): kappa1 / A(1).
  double drift_total() const;
};

/// Fits `structure` to the identification phases of `data` (the val phase is never used). For a backlash,
/// `initial` (optional, same config) gives a second starting point for the operator's regimes; with
/// `only_from_initial`, the only one (the switch's regimes, the other start, are a poor guess behind an input lag,
/// and a search over lambda that starts every fit from a good model saves half its time).
JointModel fit_joint_model(const ExperimentConfig& config, const FlatRecording& data, const ModelStructure& structure,
                           const JointModel* initial = nullptr, bool only_from_initial = false);

/// The command w(t) the operator sees: v delayed by d, then through G(lambda) (at rest on v(0) before t = 0).
std::vector<double> effective_input(const std::vector<double>& v, const ModelStructure& structure);

/// u~(t) of the fitted operator for the whole recording (state from t = 0: on C_d at w(0)).
std::vector<double> operator_output(const JointModel& model, const FlatRecording& data);

/// Pure simulation of the model over samples [begin, end): the past before `begin` is the measured output
/// (the state carried over from the recording), the operator state comes from running it from t = 0.
std::vector<double> simulate_segment(const JointModel& model, const FlatRecording& data, std::size_t begin,
                                     std::size_t end);

/// Fit (%) of the model's pure simulation over [begin, end) (simulate_segment) to the measured y there; -infinity
/// when the simulation diverges (an unstable model is the worst model, not an error). `simulated`, when given,
/// receives the simulation.
double simulation_fit(const JointModel& model, const FlatRecording& data, std::size_t begin, std::size_t end,
                      std::vector<double>* simulated = nullptr);

/// The model's own one-step squared error over its residual rows (residual_t): its operator run on its own borders,
/// so a backlash takes the regimes its borders give. `rss` is instead the regression's error with the regimes the
/// model was fitted with; the two differ where a fit's borders would make its backlash move or hold elsewhere.
double self_consistent_rss(const JointModel& model, const FlatRecording& data);

/// `model` with a known plant in place of its estimates, on `model`'s own border tables and in its scaling (3.11c):
/// a and b (b_1..b_n, the plant's units) and the borders sampled at the tables' abscissas, u~ = (F - u_M) / K with
/// u_M = C_d(v_max), K = u_M - C_d(v_min), b scaled by K, kappa0 = B(1) u_M (kappa1 is kept). For checking a fit
/// against the generator's truth. Throws std::invalid_argument when the sizes of a or b are not model.n or K = 0.
JointModel with_true_plant(const JointModel& model, const std::vector<double>& a, const std::vector<double>& b,
                           const Border& ascending, const Border& descending);

/// A known plant on the border tables of `config` with `border_segments` segments per interval (the tables a fit with
/// that structure has), as with_true_plant puts it: for research (diagnose-sweep --oracle-regimes), where the true
/// plant is the start of a fit. Throws std::invalid_argument as with_true_plant, or when V_d or V_a lacks m points.
JointModel true_plant_on_tables(const ExperimentConfig& config, int border_segments, const std::vector<double>& a,
                                const std::vector<double>& b, const Border& ascending, const Border& descending);

/// One-step prediction errors y(t) - y^(t|t-1) over [begin, end) (t >= n).
std::vector<double> prediction_errors(const JointModel& model, const FlatRecording& data, std::size_t begin,
                                      std::size_t end);

}  // namespace lashid::sim
