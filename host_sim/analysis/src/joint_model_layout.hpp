// The border tables and the operator basis of the joint model (joint_model.cpp): where the border points are,
// which of them are smoothed, and the hat weights phi(t) of the operator's input on the border it moves along.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "lashid/analysis/joint_model.hpp"
#include "lashid/io/config.hpp"

namespace lashid::sim::detail {

// Node abscissas of one border and, per node, the index of its value in c (-1: the reference u~ = 0 at v_max).
struct BorderLayout {
  std::vector<double> x;
  std::vector<int> param;
};

// phi(t): the hat weights of w(t) on one border, i.e. at most two border parameters (-1: none). Stored sparse:
// the regression is accumulated from these few entries per row rather than from a dense design matrix, which
// makes one fit cheap enough for the hundreds the diagnosis runs per recording.
struct HatRow {
  std::array<int, 2> param{-1, -1};
  std::array<double, 2> weight{0.0, 0.0};
  friend bool operator==(const HatRow&, const HatRow&) = default;
};
using Basis = std::vector<HatRow>;

/// The value sum_j weight_j c(param_j) of a hat row for border values given by `c` (a callable of the parameter
/// index, or an Eigen vector); the reference (-1) contributes nothing.
template <class Values>
double hat_value(const HatRow& h, const Values& c) {
  double v = 0;
  for (std::size_t j = 0; j < 2; ++j) {
    if (h.param[j] >= 0) v += h.weight[j] * c(h.param[j]);
  }
  return v;
}

// A point between the levels, pulled towards the line through its two neighbours on the same border: the
// smoothness prior that keeps points the data hardly reach from taking wild values. Parameter -1 is the reference
// u~ = 0 (a constant, so it drops out of the penalty).
struct SmoothnessStencil {
  int left = -1, centre = -1, right = -1;
  double left_weight = 0, right_weight = 0;  // of the linear interpolation at the centre
};

struct Layout {
  BorderLayout ascending, descending;
  int parameters = 0;        // 2m - 1, plus the points between the abscissas
  int level_parameters = 0;  // 2m - 1: the values at the experiment's abscissas
  std::vector<SmoothnessStencil> stencils;  // one per point between the abscissas
};

/// The layout of `c`'s borders with `segments` equal segments per interval between the experiment's abscissas.
/// Throws std::invalid_argument when V_d or V_a does not have m points.
Layout make_layout(const ExperimentConfig& c, int segments);

/// The vector c of `layout`'s border parameters from `model`'s border values (which must be on `layout`'s
/// abscissas); the references (parameter -1) have no entry.
Eigen::VectorXd border_parameters(const JointModel& model, const Layout& layout);

/// The hat-function weights of w on one border (w outside the nodes is clamped, as Border does).
HatRow hat_row(const BorderLayout& border, double w);
/// The same, its search started from `hint` (lashid/plant/nearby_search.hpp), which it moves: the same row.
HatRow hat_row(const BorderLayout& border, double w, std::size_t& hint);

/// phi(t) for every sample: the hat weights on the border the operator moves along, or phi(t-1) while it holds.
/// The switch's regime depends on the direction of w only; the backlash's also on the borders, taken from
/// `current` (the previous fit) when given, otherwise the switch's regimes are used as the first guess.
Basis operator_basis(const Layout& layout, const std::vector<double>& w, OperatorKind op, const JointModel* current);

/// A backlash's play made non-negative on its finer tables: C~_a lowered to C~_d where it lies above it, C~_d
/// raised to C~_a (ModelStructure::non_negative_play; each table's other border read linearly between its points).
void give_non_negative_play(JointModel& model);

}  // namespace lashid::sim::detail
