// Recursive least squares for the DIS/AIS regression (3.19) that exploits its structure: exact (3.21) at any time,
// O(n^2) work per sample, accurate in float32 over 10^6 samples and more. See docs/estimator.md for the derivation.
//
// On the design, a row Phi(t) = [phi_y(t); input part] has at most one non-zero input entry, at column k, and its
// value is always the same number w_k = W_l (RegressorBuilder). Rows therefore fall into groups: g = 0 (no input
// entry) and g = k + 1 (entry in column k). Minimising sum (y~ - phi_y'a - mu_k w_k)^2 over mu_k gives
// mu_k w_k = mean over group k of (y~ - phi_y'a), and (3.21) reduces exactly to the n x n system
//     [sum_{g>=1} S_g + R_0] a = (same, column y~),   mu_k = (ybar_k - phibar_k' a) / w_k,
// with S_g the scatter (centred second moment) of z = [phi_y; y~] within group g and R_0 the raw second moment of
// group 0. The per-group moments are kept with Welford's update and, every kBlock rows, merged into running totals
// with Chan-Golub-LeVeque's pairwise formula, so rounding grows like (kBlock + count / kBlock) eps instead of
// count * eps. Nothing is ever subtracted from a large accumulated sum, unlike the covariance form of RLS, whose
// P = (Phi'Phi)^-1 loses symmetry and positive definiteness in float32 (cond(Phi'Phi) ~ 1.7e6 here).
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "lashid/estimator/least_squares.hpp"
#include "lashid/estimator/regressor.hpp"
#include "lashid/estimator/symmetric_eigenvalues.hpp"

namespace lashid::est {

template <class Scalar, int N, int M>
class GroupedLeastSquares {
 public:
  static constexpr int kDim = N + N * M;
  static constexpr int kGroups = N * M + 1;
  static constexpr int kZ = N + 1;  // z = [phi_y; y~]
  static constexpr std::uint32_t kBlock = 64;
  using Builder = RegressorBuilder<Scalar, N, M>;
  using Solution = LsSolution<Scalar, N, M>;
  using ZVec = Eigen::Matrix<Scalar, kZ, 1>;
  using ZMat = Eigen::Matrix<Scalar, kZ, kZ>;
  using NMat = Eigen::Matrix<Scalar, N, N>;
  using NVec = Eigen::Matrix<Scalar, N, 1>;

  /// Running count, mean and scatter (upper triangle) of z within one group.
  struct Moments {
    std::uint32_t count = 0;
    ZVec mean = ZVec::Zero();
    ZMat scatter = ZMat::Zero();

    void add(const ZVec& z) {
      ++count;
      const ZVec delta = z - mean;
      const Scalar inv = Scalar(1) / static_cast<Scalar>(count);
      mean += delta * inv;
      // z - mean_new = delta (count-1)/count, so the Welford term delta (z - mean_new)' is a symmetric rank-1 update.
      // Written out on the upper triangle: Eigen's generic rankUpdate costs about twice as much at this size.
      // Unrolled: rolled, GCC -O2 spends more instructions on the loop than on the 6 multiply-adds (Cortex-M4F: 137
      // -> 86 per update, docs/on-target-cost.md). Same operations in the same order.
      const Scalar f = Scalar(1) - inv;
#pragma GCC unroll 8
      for (int j = 0; j < kZ; ++j) {
        const Scalar dj = delta(j) * f;
#pragma GCC unroll 8
        for (int i = 0; i <= j; ++i) scatter(i, j) += delta(i) * dj;
      }
    }

    void merge(const Moments& other) {
      if (other.count == 0) return;
      if (count == 0) {
        *this = other;
        return;
      }
      const Scalar na = static_cast<Scalar>(count);
      const Scalar nb = static_cast<Scalar>(other.count);
      const Scalar n = na + nb;
      const ZVec delta = other.mean - mean;
      mean += delta * (nb / n);
      scatter.template triangularView<Eigen::Upper>() += other.scatter;
      scatter.template selfadjointView<Eigen::Upper>().rankUpdate(delta, na * nb / n);
      count += other.count;
    }
  };

  GroupedLeastSquares() = default;
  explicit GroupedLeastSquares(const typename Builder::Basis::Nodes& W) { reset(W); }

  void reset(const typename Builder::Basis::Nodes& W) {
    for (int k = 0; k < N * M; ++k) w_(k) = W(k / N);
    for (int g = 0; g < kGroups; ++g) {
      total_[g] = Moments{};
      block_[g] = Moments{};
    }
  }

  /// Largest condition number of the reduced n x n matrix accepted before solve() reports kIllConditioned.
  static constexpr Scalar min_rcond() { return Scalar(256) * Eigen::NumTraits<Scalar>::epsilon(); }

  /// Adds the row Phi(t) (from the builder, before it is given sample t) with target y~(t).
  Status update(const Builder& builder, Scalar y_tilde) {
    SparseRegressor<Scalar, N, M> row;
    const Status s = builder.sparse(row);
    if (s != Status::kOk) return s;
    return update(row, y_tilde);
  }

  Status update(const SparseRegressor<Scalar, N, M>& row, Scalar y_tilde) {
    if (!std::isfinite(y_tilde) || !row.phi_y.allFinite()) return Status::kNonFinite;
    const int g = row.input_column + 1;
    ZVec z;
    z.template head<N>() = row.phi_y;
    z(N) = y_tilde;
    Moments& block = block_[g];
    block.add(z);
    if (block.count == kBlock) {
      total_[g].merge(block);
      block = Moments{};
    }
    return Status::kOk;
  }

  /// Number of rows seen so far.
  std::uint32_t rows() const {
    std::uint32_t r = 0;
    for (int g = 0; g < kGroups; ++g) r += total_[g].count + block_[g].count;
    return r;
  }

  /// Least-squares estimate of Theta from all rows so far (same value as (3.21) on these rows). Standard errors
  /// (and the residual variance) only when asked: the periodic estimate of the firmware does not need them.
  Solution solve(bool with_std_errors = true) const {
    Solution out;
    ZMat info = ZMat::Zero();  // upper triangle of the reduced information matrix of z
    ZVec mean[static_cast<std::size_t>(kGroups)];
    std::uint32_t count[static_cast<std::size_t>(kGroups)];
    for (int g = 0; g < kGroups; ++g) {
      // The merge of total_ and block_ (Chan et al.), accumulated into info without copying the moments.
      const Moments& a = total_[g];
      const Moments& b = block_[g];
      count[g] = a.count + b.count;
      out.rows += count[g];
      add_upper(info, a.scatter);
      add_upper(info, b.scatter);
      if (a.count == 0 || b.count == 0) {
        mean[g] = a.count == 0 ? b.mean : a.mean;
        continue;
      }
      const Scalar na = static_cast<Scalar>(a.count);
      const Scalar nb = static_cast<Scalar>(b.count);
      const ZVec delta = b.mean - a.mean;
      mean[g] = a.mean + delta * (nb / (na + nb));
      add_rank_one(info, delta, na * nb / (na + nb));
    }
    // Group 0 has no free offset: its raw second moment is scatter + count * mean mean'.
    add_rank_one(info, mean[0], static_cast<Scalar>(count[0]));
    for (int g = 1; g < kGroups; ++g) {
      if (count[g] == 0) return out;  // mu for column g-1 not excited yet: kNotExcited
    }
    if (out.rows <= static_cast<std::uint32_t>(kDim)) return out;

    const ZMat full = info.template selfadjointView<Eigen::Upper>();
    const NMat A = full.template topLeftCorner<N, N>();
    const NVec r = full.template topRightCorner<N, 1>();
    out.rcond = reciprocal_condition(A);
    if (!(out.rcond >= min_rcond())) {
      out.status = Status::kIllConditioned;
      return out;
    }
    NVec a;
    NMat A_inv;
    if constexpr (N == 1) {  // a division; also keeps Eigen's 1x1 LDLT (and a GCC 12 false warning) out
      A_inv(0, 0) = Scalar(1) / A(0, 0);
      a = A_inv * r;
    } else {
      const Eigen::LDLT<NMat> ldlt(A);
      a = ldlt.solve(r);
      // Column by column: a matrix right-hand side goes through Eigen's blocked triangular solver, which links
      // malloc (its stack-or-heap workspace) even when it never calls it. The freestanding test checks this.
      if (with_std_errors) {
        for (int k = 0; k < N; ++k) A_inv.col(k) = ldlt.solve(NVec::Unit(k));
      }
    }
    out.theta.template head<N>() = a;
    for (int k = 0; k < N * M; ++k) {
      const ZVec& mk = mean[k + 1];
      out.theta(N + k) = (mk(N) - mk.template head<N>().dot(a)) / w_(k);
    }
    out.status = out.theta.allFinite() ? Status::kOk : Status::kIllConditioned;
    if (!with_std_errors || out.status != Status::kOk) return out;

    const Scalar rss = std::fmax(full(N, N) - r.dot(a), Scalar(0));
    out.noise_variance = rss / static_cast<Scalar>(out.rows - static_cast<std::uint32_t>(kDim));
    out.std_error.template head<N>() = (out.noise_variance * A_inv.diagonal()).cwiseSqrt();
    for (int k = 0; k < N * M; ++k) {
      // var(mu_k) = sigma^2 [1/(count w^2) + (phibar/w)' A^-1 (phibar/w)]: group mean and within-group slope are
      // uncorrelated.
      const NVec h = mean[k + 1].template head<N>() / w_(k);
      const Scalar var = out.noise_variance * (Scalar(1) / (static_cast<Scalar>(count[k + 1]) * w_(k) * w_(k)) +
                                               h.dot(A_inv * h));
      out.std_error(N + k) = std::sqrt(var);
    }
    return out;
  }

 private:
  // The upper-triangle loops below are unrolled (kZ = 3 for n = 2: 6 entries) for the same reason as in
  // Moments::add: solve() merges 13 groups with them (Cortex-M4F: 2,680 -> 2,000 instructions per estimate).

  // info += s on the upper triangle (what triangularView<Upper>() += s computes).
  static void add_upper(ZMat& info, const ZMat& s) {
#pragma GCC unroll 8
    for (int j = 0; j < kZ; ++j) {
#pragma GCC unroll 8
      for (int i = 0; i <= j; ++i) info(i, j) += s(i, j);
    }
  }

  // info += alpha v v' on the upper triangle.
  static void add_rank_one(ZMat& info, const ZVec& v, Scalar alpha) {
#pragma GCC unroll 8
    for (int j = 0; j < kZ; ++j) {
      const Scalar vj = v(j) * alpha;
#pragma GCC unroll 8
      for (int i = 0; i <= j; ++i) info(i, j) += v(i) * vj;
    }
  }

  static Scalar reciprocal_condition(const NMat& A) {
    if constexpr (N == 1) {
      return A(0, 0) > Scalar(0) && std::isfinite(A(0, 0)) ? Scalar(1) : Scalar(0);
    } else if constexpr (N == 2) {
      // Closed form for a symmetric 2x2: lambda = (tr -+ sqrt((a-d)^2 + 4b^2)) / 2.
      if (!A.allFinite()) return Scalar(0);
      const Scalar half_tr = Scalar(0.5) * (A(0, 0) + A(1, 1));
      const Scalar half_gap = std::hypot(Scalar(0.5) * (A(0, 0) - A(1, 1)), A(0, 1));
      const Scalar hi = half_tr + half_gap;
      return hi > Scalar(0) ? std::fmax(half_tr - half_gap, Scalar(0)) / hi : Scalar(0);
    } else {
      return reciprocal_condition_spd<Scalar, N>(A);
    }
  }

  Eigen::Matrix<Scalar, N * M, 1> w_ = Eigen::Matrix<Scalar, N * M, 1>::Ones();
  Moments total_[static_cast<std::size_t>(kGroups)];
  Moments block_[static_cast<std::size_t>(kGroups)];
};

}  // namespace lashid::est
