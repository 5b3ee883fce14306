// Recursive least squares for the DIS/AIS regression (3.19) that exploits its structure: exact (3.21) at any time,
// O(n^2) work per sample, accurate in float32 up to kMaxPulseLength = 2^28 rows (design.hpp; measured to 3.2e8). See
// docs/estimator.md for the derivation and the limits.
//
// On the design, a row Phi(t) = [phi_y(t); input part] has at most one non-zero input entry, at column k, and its
// value is always the same number w_k = W_l (RegressorBuilder). Rows therefore fall into groups: g = 0 (no input
// entry) and g = k + 1 (entry in column k). Minimising sum (y~ - phi_y'a - mu_k w_k)^2 over mu_k gives
// mu_k w_k = mean over group k of (y~ - phi_y'a), and (3.21) reduces exactly to the n x n system
//     [sum_{g>=1} S_g + R_0] a = (same, column y~),   mu_k = (ybar_k - phibar_k' a) / w_k,
// with S_g the scatter (centred second moment) of z = [phi_y; y~] within group g and R_0 the raw second moment of
// group 0. Only the SUM of the scatters enters, so one scatter is kept for all groups, and per group only a count
// and a mean: with the firmware's capacity (n <= 4, m <= 10: 41 groups) that is 2 KiB of float32 state instead of
// 10 KiB. The rows are added with Welford's update into a block (per-group mean, shared scatter); every kBlock rows
// of a group, its block mean is merged into its running total with Chan-Golub-LeVeque's pairwise formula (the
// rank-one term between the two means goes into the shared scatter). The shared scatter is summed in three levels
// (kBlock rows, kBlock blocks, the rest), so rounding grows like (2 kBlock + count / kBlock^2) eps instead of
// count * eps: with two levels, one shared sum over all groups lost a factor of 4 in float32 accuracy after 10^6
// rows against per-group sums (tests/test_estimator.cpp, docs/estimator.md). Nothing is ever subtracted from a large accumulated sum, unlike the covariance form of RLS, whose
// P = (Phi'Phi)^-1 loses symmetry and positive definiteness in float32 (cond(Phi'Phi) ~ 1.7e6 here).
//
// N and M are capacities (fixed-size storage); the order n <= N and points m <= M are chosen by reset(). The per-row
// update and solve()'s merge over the groups are compiled once per order 1..N and chosen by n at run time
// (order_dispatch.hpp), so that their loops stay unrolled; the n x n algebra, once per solve, is one routine for
// every n (SmallCholesky), which keeps the firmware image small.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <utility>

#include <Eigen/Core>

#include "lashid/estimator/least_squares.hpp"
#include "lashid/estimator/order_dispatch.hpp"
#include "lashid/estimator/regressor.hpp"
#include "lashid/estimator/small_cholesky.hpp"
#include "lashid/estimator/symmetric_eigenvalues.hpp"

namespace lashid::est {

template <class Scalar, int N, int M>
class GroupedLeastSquares {
 public:
  static constexpr int kDim = N + N * M;     ///< capacity of Theta
  static constexpr int kGroups = N * M + 1;  ///< capacity in groups
  static constexpr int kZ = N + 1;           ///< capacity of z = [phi_y; y~]
  static constexpr std::uint32_t kBlock = 64;
  using Builder = RegressorBuilder<Scalar, N, M>;
  using Solution = LsSolution<Scalar, N, M>;
  using ZVec = Eigen::Matrix<Scalar, kZ, 1>;
  using ZMat = Eigen::Matrix<Scalar, kZ, kZ>;
  using NMat = Eigen::Matrix<Scalar, N, N>;
  using NVec = Eigen::Matrix<Scalar, N, 1>;

  /// Count and mean of z within one group (over the current block, or over all merged blocks).
  struct GroupMean {
    std::uint32_t count = 0;
    ZVec mean = ZVec::Zero();
  };

  GroupedLeastSquares() = default;
  explicit GroupedLeastSquares(const typename Builder::Basis::Nodes& W, int n = N, int m = M) {
    (void)reset(W, n, m);
  }

  /// Clears all rows and sets the order n and points m. kOrderOutOfRange (and nothing usable) outside capacity.
  Status reset(const typename Builder::Basis::Nodes& W, int n = N, int m = M) {
    valid_ = n >= 1 && n <= N && m >= 1 && m <= M;
    n_ = valid_ ? n : 1;
    m_ = valid_ ? m : 1;
    groups_ = n_ * m_ + 1;
    w_.setOnes();
    for (int k = 0; k < n_ * m_; ++k) w_(k) = W(k / n_);
    for (int g = 0; g < kGroups; ++g) {
      total_[g] = GroupMean{};
      block_[g] = GroupMean{};
    }
    total_scatter_.setZero();
    middle_scatter_.setZero();
    block_scatter_.setZero();
    block_rows_ = 0;
    middle_blocks_ = 0;
    return valid_ ? Status::kOk : Status::kOrderOutOfRange;
  }

  int order() const { return n_; }
  int points() const { return m_; }
  /// Entries of Theta at this n, m.
  int dim() const { return n_ + n_ * m_; }

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
    if (!valid_) return Status::kOrderOutOfRange;
    Status s = Status::kOk;
    with_order<N>(n_, [&](auto order) { s = update_n<decltype(order)::value>(row, y_tilde); });
    return s;
  }

  /// update() for the order Nn = n, known at compile time (the caller dispatched on n, and reset() accepted it).
  template <int Nn>
  Status update_n(const SparseRegressor<Scalar, N, M>& row, Scalar y_tilde) {
    static_assert(Nn >= 1 && Nn <= N);
    // Summed, one test: the sum of the differences is NaN as soon as one of them is (x - x is NaN for inf and NaN).
    Scalar zero = y_tilde - y_tilde;
#pragma GCC unroll 8
    for (int i = 0; i < Nn; ++i) zero += row.phi_y(i) - row.phi_y(i);
    if (!(zero == Scalar(0))) return Status::kNonFinite;
    const int g = row.input_column + 1;
    GroupMean& block = block_[g];
    add_to_block<Nn + 1>(block, row.phi_y, y_tilde);
    if (block.count == kBlock) merge_block<Nn + 1>(g);
    if (++block_rows_ == kBlock) end_block<Nn + 1>();
    return Status::kOk;
  }

  /// Number of rows seen so far.
  std::uint32_t rows() const {
    std::uint32_t r = 0;
    for (int g = 0; g < groups_; ++g) r += total_[g].count + block_[g].count;
    return r;
  }

  /// Least-squares estimate of Theta from all rows so far (same value as (3.21) on these rows). Standard errors
  /// (and the residual variance) only when asked: the periodic estimate of the firmware does not need them.
  Solution solve(bool with_std_errors = true) const {
    Solution out;
    solve_into(out, with_std_errors);
    return out;
  }

  /// solve() into `out`, without building a Solution: only the first n + n m entries of theta and std_error are
  /// written (the others keep their values), so that a caller re-solving into the same object every period neither
  /// clears nor copies the capacity's entries (the firmware: about 1,000 instructions per solve at n <= 4, m <= 10).
  void solve_into(Solution& out, bool with_std_errors = true) const {
    out.n = n_;
    out.m = m_;
    out.rows = 0;
    out.rcond = Scalar(0);
    out.noise_variance = Scalar(0);
    out.status = Status::kNotExcited;
    if (!valid_) {
      out.status = Status::kOrderOutOfRange;
      return;
    }
    const int n = n_;
    ZMat info;  // upper triangle of the reduced information matrix of z (leading n + 1 block)
    ZVec mean[static_cast<std::size_t>(kGroups)];
    std::uint32_t count[static_cast<std::size_t>(kGroups)];
    with_order<N>(n, [&](auto order) { merge_groups<decltype(order)::value + 1>(info, mean, count, out.rows); });
    for (int g = 1; g < groups_; ++g) {
      if (count[g] == 0) return;  // mu for column g-1 not excited yet: kNotExcited
    }
    if (out.rows <= static_cast<std::uint32_t>(dim())) return;

    NMat A;
    NVec a;  // first r, then the solution
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i <= j; ++i) A(i, j) = A(j, i) = info(i, j);
      a(j) = info(j, n);
    }
    out.rcond = reciprocal_condition(A, n);
    SmallCholesky<Scalar, N> chol;
    if (!(out.rcond >= min_rcond()) || !chol.compute(A, n)) {
      out.status = Status::kIllConditioned;
      return;
    }
    const NVec r = a;
    chol.solve_in_place(a);
    bool finite = true;
    for (int i = 0; i < n; ++i) {
      out.theta(i) = a(i);
      finite = finite && std::isfinite(a(i));
    }
    for (int k = 0; k < n * m_; ++k) {
      const ZVec& mk = mean[k + 1];
      out.theta(n + k) = (mk(n) - head_dot(mk, a, n)) / w_(k);
      finite = finite && std::isfinite(out.theta(n + k));
    }
    out.status = finite ? Status::kOk : Status::kIllConditioned;
    if (!with_std_errors || out.status != Status::kOk) return;

    NMat A_inv;
    for (int k = 0; k < n; ++k) {
      NVec e = NVec::Zero();
      e(k) = Scalar(1);
      chol.solve_in_place(e);
      A_inv.col(k) = e;
    }
    const Scalar rss = std::fmax(info(n, n) - head_dot(r, a, n), Scalar(0));
    out.noise_variance = rss / static_cast<Scalar>(out.rows - static_cast<std::uint32_t>(dim()));
    for (int i = 0; i < n; ++i) out.std_error(i) = std::sqrt(out.noise_variance * A_inv(i, i));
    for (int k = 0; k < n * m_; ++k) {
      // var(mu_k) = sigma^2 [1/(count w^2) + (phibar/w)' A^-1 (phibar/w)]: group mean and within-group slope are
      // uncorrelated.
      NVec h;
      for (int i = 0; i < n; ++i) h(i) = mean[k + 1](i) / w_(k);
      Scalar quad = Scalar(0);
      for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) quad += h(i) * A_inv(i, j) * h(j);
      }
      const Scalar var =
          out.noise_variance * (Scalar(1) / (static_cast<Scalar>(count[k + 1]) * w_(k) * w_(k)) + quad);
      out.std_error(n + k) = std::sqrt(var);
    }
  }

 private:
  // The reduced information matrix of z = [phi_y; y~] (upper triangle, leading K x K block) and each group's count
  // and mean over all its rows: the shared scatter's three levels, plus the Chan et al. merge of each group's
  // total and block, accumulated without copying the moments.
  template <int K>
  void merge_groups(ZMat& info, ZVec* mean, std::uint32_t* count, std::uint32_t& rows) const {
#pragma GCC unroll 8
    for (int j = 0; j < K; ++j) {
#pragma GCC unroll 8
      for (int i = 0; i <= j; ++i) info(i, j) = total_scatter_(i, j) + middle_scatter_(i, j) + block_scatter_(i, j);
    }
    for (int g = 0; g < groups_; ++g) {
      const GroupMean& a = total_[g];
      const GroupMean& b = block_[g];
      count[g] = a.count + b.count;
      rows += count[g];
      if (a.count == 0 || b.count == 0) {
        mean[g] = a.count == 0 ? b.mean : a.mean;
        continue;
      }
      const Scalar na = static_cast<Scalar>(a.count);
      const Scalar nb = static_cast<Scalar>(b.count);
      const Scalar w = nb / (na + nb);
      ZVec delta;
#pragma GCC unroll 8
      for (int i = 0; i < K; ++i) {
        delta(i) = b.mean(i) - a.mean(i);
        mean[g](i) = a.mean(i) + delta(i) * w;
      }
      add_rank_one<K>(info, delta, na * w);
    }
    // Group 0 has no free offset: its raw second moment is scatter + count * mean mean'.
    add_rank_one<K>(info, mean[0], static_cast<Scalar>(count[0]));
  }

  // sum_{i < n} x(i) a(i), for x a z-vector (its phi_y part) or an n-vector.
  template <class Vec>
  static Scalar head_dot(const Vec& x, const NVec& a, int n) {
    Scalar s = Scalar(0);
    for (int i = 0; i < n; ++i) s += x(i) * a(i);
    return s;
  }

  // Welford's update of the group's block mean; the scatter term goes into the shared block scatter. z - mean_new
  // = delta (count-1)/count, so the term delta (z - mean_new)' is a symmetric rank-1 update, written out on the
  // upper triangle: Eigen's generic rankUpdate costs about twice as much at this size, and a rolled loop spends more
  // instructions on the loop than on the multiply-adds (Cortex-M4F: 137 -> 86 per update at n = 2).
  template <int K>
  void add_to_block(GroupMean& block, const NVec& phi_y, Scalar y_tilde) {
    ++block.count;
    Eigen::Matrix<Scalar, K, 1> delta;
#pragma GCC unroll 8
    for (int i = 0; i < K - 1; ++i) delta(i) = phi_y(i) - block.mean(i);
    delta(K - 1) = y_tilde - block.mean(K - 1);
    const Scalar inv = Scalar(1) / static_cast<Scalar>(block.count);
#pragma GCC unroll 8
    for (int i = 0; i < K; ++i) block.mean(i) += delta(i) * inv;
    const Scalar f = Scalar(1) - inv;
#pragma GCC unroll 8
    for (int j = 0; j < K; ++j) {
      const Scalar dj = delta(j) * f;
#pragma GCC unroll 8
      for (int i = 0; i <= j; ++i) block_scatter_(i, j) += delta(i) * dj;
    }
  }

  // Chan et al.'s merge of group g's block into its total; the rank-one term goes into the shared scatter.
  template <int K>
  void merge_block(int g) {
    GroupMean& a = total_[g];
    GroupMean& b = block_[g];
    if (a.count == 0) {
      a = b;
    } else {
      const Scalar na = static_cast<Scalar>(a.count);
      const Scalar nb = static_cast<Scalar>(b.count);
      const Scalar n = na + nb;
      const ZVec delta = b.mean - a.mean;
      a.mean += delta * (nb / n);
      add_rank_one<K>(middle_scatter_, delta, na * nb / n);
      a.count += b.count;
    }
    b = GroupMean{};
  }

  // The shared scatter's block ends every kBlock rows, whatever their groups; every kBlock blocks, the middle level.
  template <int K>
  void end_block() {
    add_upper<K>(middle_scatter_, block_scatter_);
    block_scatter_.setZero();
    block_rows_ = 0;
    if (++middle_blocks_ == kBlock) {
      add_upper<K>(total_scatter_, middle_scatter_);
      middle_scatter_.setZero();
      middle_blocks_ = 0;
    }
  }

  // info += s on the upper triangle of the leading K x K block (what triangularView<Upper>() += s computes).
  template <int K, class Info>
  static void add_upper(Info& info, const ZMat& s) {
#pragma GCC unroll 8
    for (int j = 0; j < K; ++j) {
#pragma GCC unroll 8
      for (int i = 0; i <= j; ++i) info(i, j) += s(i, j);
    }
  }

  // info += alpha v v' on the upper triangle of the leading K x K block, unrolled (solve() merges every group with
  // it: Cortex-M4F 2,680 -> 2,000 instructions per estimate at n = 2, m = 6).
  template <int K, class Info, class Vec>
  static void add_rank_one(Info& info, const Vec& v, Scalar alpha) {
#pragma GCC unroll 8
    for (int j = 0; j < K; ++j) {
      const Scalar vj = v(j) * alpha;
#pragma GCC unroll 8
      for (int i = 0; i <= j; ++i) info(i, j) += v(i) * vj;
    }
  }

  static Scalar reciprocal_condition(const NMat& A, int n) {
    if (n == 1) return A(0, 0) > Scalar(0) && std::isfinite(A(0, 0)) ? Scalar(1) : Scalar(0);
    if constexpr (N >= 2) {
      if (n == 2) {
        // Closed form for a symmetric 2x2: lambda = (tr -+ sqrt((a-d)^2 + 4b^2)) / 2.
        if (!std::isfinite(A(0, 0)) || !std::isfinite(A(0, 1)) || !std::isfinite(A(1, 1))) return Scalar(0);
        const Scalar half_tr = Scalar(0.5) * (A(0, 0) + A(1, 1));
        const Scalar half_gap = std::hypot(Scalar(0.5) * (A(0, 0) - A(1, 1)), A(0, 1));
        const Scalar hi = half_tr + half_gap;
        return hi > Scalar(0) ? std::fmax(half_tr - half_gap, Scalar(0)) / hi : Scalar(0);
      }
      return reciprocal_condition_spd<Scalar, N>(A, n);
    } else {
      return Scalar(0);  // unreachable: n <= N = 1
    }
  }

  int n_ = N;
  int m_ = M;
  int groups_ = kGroups;
  bool valid_ = true;
  Eigen::Matrix<Scalar, N * M, 1> w_ = Eigen::Matrix<Scalar, N * M, 1>::Ones();
  GroupMean total_[static_cast<std::size_t>(kGroups)];
  GroupMean block_[static_cast<std::size_t>(kGroups)];
  // Upper triangles of the shared scatter in three levels: the current block of kBlock rows, the current kBlock
  // blocks (with the merges' rank-one terms), and the rest.
  ZMat total_scatter_ = ZMat::Zero();
  ZMat middle_scatter_ = ZMat::Zero();
  ZMat block_scatter_ = ZMat::Zero();
  std::uint32_t block_rows_ = 0;
  std::uint32_t middle_blocks_ = 0;
};

}  // namespace lashid::est
