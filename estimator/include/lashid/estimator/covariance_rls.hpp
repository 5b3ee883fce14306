// Textbook recursive least squares in covariance form (e.g. Ljung, System Identification, 2nd ed., eq. 11.13;
// Astrom & Wittenmark, Adaptive Control, Sec. 2.2):
//   K = P phi / (1 + phi' P phi),  theta += K (y - phi' theta),  P -= K phi' P,   P(0) = p0 I.
// Kept only as the baseline of the benchmarks and of the float32 long-run test: O(dim^2) per sample, and in
// float32 P loses symmetry and positive definiteness on this problem. The project's estimator is
// GroupedLeastSquares.
#pragma once

#include <cmath>
#include <cstdint>

#include <Eigen/Core>

#include "lashid/estimator/least_squares.hpp"
#include "lashid/estimator/regressor.hpp"

namespace lashid::est {

template <class Scalar, int N, int M>
class CovarianceRls {
 public:
  static constexpr int kDim = N + N * M;
  using Builder = RegressorBuilder<Scalar, N, M>;
  using Solution = LsSolution<Scalar, N, M>;
  using Matrix = Eigen::Matrix<Scalar, kDim, kDim>;
  using Vector = Eigen::Matrix<Scalar, kDim, 1>;

  CovarianceRls() = default;
  explicit CovarianceRls(const typename Builder::Basis::Nodes& W, Scalar p0 = Scalar(1e6)) : p0_(p0) { (void)reset(W); }

  /// Clears all rows. This dense back-end is compiled for exactly n = N, m = M: kOrderOutOfRange otherwise.
  Status reset(const typename Builder::Basis::Nodes& /*W*/, int n = N, int m = M) {
    P_ = Matrix::Identity() * p0_;
    theta_.setZero();
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
    const Vector Pphi = P_ * phi;
    const Scalar denom = Scalar(1) + phi.dot(Pphi);
    if (!(denom > Scalar(0))) return Status::kIllConditioned;  // P has lost positive definiteness
    const Vector K = Pphi / denom;
    theta_ += K * (y_tilde - phi.dot(theta_));
    P_.noalias() -= K * Pphi.transpose();
    ++rows_;
    return Status::kOk;
  }

  std::uint32_t rows() const { return rows_; }
  const Matrix& covariance() const { return P_; }

  Solution solve() const {
    Solution out;
    out.rows = rows_;
    out.theta = theta_;
    out.status = rows_ > static_cast<std::uint32_t>(kDim) && theta_.allFinite() ? Status::kOk : Status::kNotExcited;
    return out;
  }

 private:
  Scalar p0_ = Scalar(1e6);
  Matrix P_ = Matrix::Identity() * Scalar(1e6);
  Vector theta_ = Vector::Zero();
  std::uint32_t rows_ = 0;
};

}  // namespace lashid::est
