// Regime consistency of a backlash fit (docs/diagnose-history.md, "Where a backlash's lambda is lost").
//
// A backlash's regimes (which samples move along a border, which hold) come from its borders; least squares fits
// the borders for given regimes and does not see the condition that makes those regimes the model's own: while the
// backlash holds, its border must not reach the held level anywhere on the way (Border::reaches); where it starts
// to move, the border must have reached it. Border values that no moving sample determines (left to the smoothness
// prior) then put the model's own backlash elsewhere, and its own one-step error is far above the regression's.
// Here each broken condition becomes a penalty row on the border values, added to the normal equations; the rows
// are chosen by an active set over a few refits.
#pragma once

#include <array>
#include <vector>

#include "joint_model_layout.hpp"
#include "joint_model_regression.hpp"
#include "lashid/analysis/joint_model.hpp"

namespace lashid::sim::detail {

/// Weight of a penalty row, in samples: large enough to hold a border point in place against the data.
inline constexpr double kConsistencyWeight = 1e3;
/// Margin, in u~ (the scaling of (3.11c): the rise C_d(v_max) - C_d(v_min) is 1), by which a border is held on
/// its side of a held level, or made to cross it.
inline constexpr double kConsistencyMargin = 1e-3;
/// Refits of the active set at most per least-squares fit.
inline constexpr int kConsistencyRounds = 6;

/// One penalty row: sum_j weight_j c[param_j] - target b_i = 0 in every product block i (the products are b_i c;
/// parameter 0 is C~_d(v_min) = -1, so b_i = -b_i c_0). Parameter -1 is the reference u~ = 0 (no column).
struct ConsistencyRow {
  std::array<int, 4> param{-1, -1, -1, -1};
  std::array<double, 4> weight{0, 0, 0, 0};
  double target = 0;
};
using ConsistencyRows = std::vector<ConsistencyRow>;

/// Adds kConsistencyWeight x each row squared, per product block, to the normal equations.
void add_consistency_rows(const ConsistencyRows& rows, int n, int P, NormalEquations& ne);

/// The identification samples where `model`'s own backlash, put in phi's state at t - 1, does not take phi's
/// regime at t (its own step, BacklashOperator), with a row for each (appended to `rows`, `used[t]` set): while
/// phi holds, the border stays on the side of the held level it started on, by kConsistencyMargin, at w(t) and at
/// the table's nodes inside the step; where phi starts to move, it crosses by the margin at w(t), or at the node
/// where `source` (the model phi's regimes came from; nullptr: the switch's regimes) crossed. Samples marked in
/// `sticky` keep their rows while the fit presses against them (a row is released once the data pull the border
/// past its margin: the sign of its multiplier). Returns the number of samples whose regime `model` breaks.
int regime_violations(const Layout& layout, const std::vector<double>& w, const FlatRecording& data,
                      const Basis& phi, const JointModel* source, const JointModel& model,
                      const std::vector<char>& sticky, std::vector<char>& used, ConsistencyRows& rows);

}  // namespace lashid::sim::detail
