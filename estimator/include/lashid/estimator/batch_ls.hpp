// Batch least squares (3.21) on the dense regressor (3.19b), in the normal-equation form of the paper:
//   Theta_hat(N) = [sum Phi Phi']^-1 [sum Phi y~].
// The reference the recursive forms are tested against; meant for double (cond(Phi'Phi) ~ 1.7e6 on the DIS
// example leaves ~10 correct digits in double, none to spare in float). Fixed-size, heap-free.
#pragma once

#include <cmath>
#include <cstdint>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "lashid/estimator/least_squares.hpp"
#include "lashid/estimator/regressor.hpp"
#include "lashid/estimator/symmetric_eigenvalues.hpp"

namespace lashid::est {

template <class Scalar, int N, int M>
class BatchLeastSquares {
 public:
  static constexpr int kDim = N + N * M;
  using Builder = RegressorBuilder<Scalar, N, M>;
  using Solution = LsSolution<Scalar, N, M>;
  using Matrix = Eigen::Matrix<Scalar, kDim, kDim>;
  using Vector = Eigen::Matrix<Scalar, kDim, 1>;

  BatchLeastSquares() = default;
  explicit BatchLeastSquares(const typename Builder::Basis::Nodes& W) { (void)reset(W); }

  /// Clears all rows. This dense back-end is compiled for exactly n = N, m = M: kOrderOutOfRange otherwise.
  Status reset(const typename Builder::Basis::Nodes& /*W*/, int n = N, int m = M) {
    info_.setZero();
    rhs_.setZero();
    yy_ = Scalar(0);
    rows_ = 0;
    return n == N && m == M ? Status::kOk : Status::kOrderOutOfRange;
  }

  Status update(const Builder& builder, Scalar y_tilde) {
    Vector phi;
    const Status s = builder.dense(phi);
    if (s != Status::kOk) return s;
    return update(phi, y_tilde);
  }

  Status update(const Vector& phi, Scalar y_tilde) {
    if (!std::isfinite(y_tilde) || !phi.allFinite()) return Status::kNonFinite;
    info_.template selfadjointView<Eigen::Upper>().rankUpdate(phi);
    rhs_ += phi * y_tilde;
    yy_ += y_tilde * y_tilde;
    ++rows_;
    return Status::kOk;
  }

  std::uint32_t rows() const { return rows_; }

  Solution solve() const {
    Solution out;
    out.rows = rows_;
    if (rows_ <= static_cast<std::uint32_t>(kDim)) return out;
    const Matrix R = info_.template selfadjointView<Eigen::Upper>();
    out.rcond = reciprocal_condition_spd<Scalar, kDim>(R);
    if (!(out.rcond >= Scalar(256) * Eigen::NumTraits<Scalar>::epsilon())) {
      out.status = Status::kIllConditioned;
      return out;
    }
    const Eigen::LDLT<Matrix> ldlt(R);
    out.theta = ldlt.solve(rhs_);
    const Scalar rss = std::fmax(yy_ - rhs_.dot(out.theta), Scalar(0));
    out.noise_variance = rss / static_cast<Scalar>(rows_ - static_cast<std::uint32_t>(kDim));
    // Diagonal of R^-1 column by column (a matrix right-hand side would link malloc, see grouped_rls.hpp).
    for (int k = 0; k < kDim; ++k) {
      const Vector column = ldlt.solve(Vector::Unit(k));
      out.std_error(k) = std::sqrt(out.noise_variance * column(k));
    }
    out.status = out.theta.allFinite() ? Status::kOk : Status::kIllConditioned;
    return out;
  }

 private:
  Matrix info_ = Matrix::Zero();
  Vector rhs_ = Vector::Zero();
  Scalar yy_ = Scalar(0);
  std::uint32_t rows_ = 0;
};

}  // namespace lashid::est
