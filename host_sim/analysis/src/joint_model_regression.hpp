// The joint model's regression (3.19) over all identification phases: its rows, and its normal equations
// (joint_model.cpp fits them).
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include <Eigen/Dense>

#include "joint_model_layout.hpp"
#include "lashid/analysis/joint_model.hpp"
#include "model_operator.hpp"

namespace lashid::sim::detail {

// The stacked regression (3.19) over the identification rows t >= n: columns a_1..a_n, the n x P products
// b_i c_p, the offset kappa0 and, with drift, kappa1. A row has at most 3n + 2 non-zero entries.
struct Entry {
  Eigen::Index column;
  double value;
};

struct RegressionShape {
  int n = 0, P = 0, cols = 0;
  std::vector<std::size_t> rows;
};

/// Row t's non-zero entries, in column order, into `entries` (cleared first): the a_i columns take -y_lags(t - i)
/// (the outputs' lags, or the instruments').
void row_entries(const RegressionShape& g, const FlatRecording& data, const ModelStructure& structure,
                 const Basis& phi, const std::vector<double>& y_lags, std::size_t t, std::vector<Entry>& entries);

// The normal equations Z'X theta = Z'Y (Z = X for least squares) and the columns' energies on the data rows.
struct NormalEquations {
  Eigen::MatrixXd zx;
  Eigen::VectorXd zy, energy;
  double yy = 0;  ///< sum of y^2 over the rows (least squares)
};

/// One lag group of a row, without branches: -y(s) in the a column and two hat weights (a missing one has weight 0
/// on the other's point, or on point 0), so that every sample adds the same fixed set of products.
struct LagGroup {
  double minus_y;
  std::array<Eigen::Index, 2> point;
  std::array<double, 2> weight;
};

/// Every sample's lag group for the basis phi: computed once per fit, for its normal equations and its residuals.
std::vector<LagGroup> lag_groups(const FlatRecording& data, const Basis& phi);

/// The columns and identification rows of the regression for n, P border parameters and `structure`.
RegressionShape regression_shape(int n, int P, const FlatRecording& data, const ModelStructure& structure);

/// Least squares (Z = X, symmetric, and the sum of y^2, from `groups` = lag_groups(data, phi)) or, with
/// `instruments_y`, instrumental variables.
NormalEquations normal_equations(const RegressionShape& g, const FlatRecording& data, const ModelStructure& structure,
                                 const Basis& phi, const std::vector<LagGroup>& groups,
                                 const std::vector<double>* instruments_y);

/// The regression's fitted values X theta on the rows of `g` (the outputs' lags), in the rows' order.
std::vector<double> fitted_values(const RegressionShape& g, const FlatRecording& data, const ModelStructure& structure,
                                  const std::vector<LagGroup>& groups, const Eigen::VectorXd& theta);

}  // namespace lashid::sim::detail
