// Result type shared by the least-squares back-ends (grouped recursive, textbook covariance RLS, batch (3.21)).
#pragma once

#include <cstdint>

#include <Eigen/Core>

#include "lashid/estimator/status.hpp"

namespace lashid::est {

/// N and M are capacities: theta holds the n + n m entries of the order n and points m solved, then zeros.
template <class Scalar, int N, int M>
struct LsSolution {
  static constexpr int kDim = N + N * M;
  using Theta = Eigen::Matrix<Scalar, kDim, 1>;

  int n = N;  ///< order solved for
  int m = M;  ///< points solved for

  Theta theta = Theta::Zero();
  Theta std_error = Theta::Zero();  ///< sqrt of the diagonal of sigma^2 (Phi^T Phi)^-1 (zero if not available)
  Scalar noise_variance = Scalar(0);  ///< residual sum of squares / (rows - dim)
  Scalar rcond = Scalar(0);           ///< reciprocal condition number of the matrix actually factorised
  std::uint32_t rows = 0;             ///< regression rows used
  Status status = Status::kNotExcited;
};

}  // namespace lashid::est
