// The linear algebra of the joint model's fit (joint_model.cpp): solving its normal equations, and the
// least-squares rank-1 model of its b_i c_k products.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Dense>

namespace lashid::sim::detail {

/// Least squares (the symmetric normal equations zx theta = zy, columns scaled to unit norm, Cholesky, whose pivots
/// give the rank) or, with `instrumental`, the instrumental-variable system Z'X theta = Z'y. Empty on failure, with
/// `failure` saying why (rank deficient, singular).
std::optional<Eigen::VectorXd> solve_normal_equations(const Eigen::MatrixXd& zx, const Eigen::VectorXd& zy,
                                                      bool instrumental, std::string& failure);

/// The least-squares model whose products b_i c_k are exactly rank one, from the unrestricted solution `theta`
/// (columns: a_1..a_n, the n x P products, then the rest; `zx`, `zy` are the normal equations restricted to the
/// columns `keep`, `yy` the sum of squared targets, `rows` the number of rows). Gauss-Newton from the best rank-1
/// factorisation of `theta`'s products (a rank-1 `theta` is a warm start); `theta` is replaced by the best point
/// reached. Returns the number of steps that lowered the objective.
int refine_rank_one(const Eigen::MatrixXd& zx, const Eigen::VectorXd& zy, const std::vector<Eigen::Index>& keep,
                    int n, int P, double yy, std::size_t rows, Eigen::VectorXd& theta);

}  // namespace lashid::sim::detail
