// Recursive least squares for the DIS/AIS regression (3.19) that exploits its structure: exact (3.21) at any time,
// O(n^2) work per sample, accurate in float32 over 10^6 samples and more. See docs/estimator.md for the derivation.
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
// N and M are capacities (fixed-size storage); the order n <= N and points m <= M are chosen by reset(). The
// per-row kernels are compiled for each z size 2..N+1 and chosen by a switch on n, so that they stay unrolled
// (Cortex-M4F: rolled loops cost about 50 more instructions per sample, docs/on-target-cost.md).
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <utility>

#include <Eigen/Core>

#include "lashid/estimator/least_squares.hpp"
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
    bool finite = std::isfinite(y_tilde);
    for (int i = 0; i < n_; ++i) finite = finite && std::isfinite(row.phi_y(i));
    if (!finite) return Status::kNonFinite;
    const int g = row.input_column + 1;
    GroupMean& block = block_[g];
    with_z_size([&](auto size) { add_to_block<decltype(size)::value>(block, row.phi_y, y_tilde); });
    if (block.count == kBlock) merge_block(g);
    if (++block_rows_ == kBlock) {  // the shared scatter's block ends every kBlock rows, whatever their groups
      add_upper(middle_scatter_, block_scatter_, n_ + 1);
      block_scatter_.setZero();
      block_rows_ = 0;
      if (++middle_blocks_ == kBlock) {
        add_upper(total_scatter_, middle_scatter_, n_ + 1);
        middle_scatter_.setZero();
        middle_blocks_ = 0;
      }
    }
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
    out.n = n_;
    out.m = m_;
    if (!valid_) {
      out.status = Status::kOrderOutOfRange;
      return out;
    }
    const int n = n_;
    const int kz = n + 1;
    ZMat info = ZMat::Zero();  // upper triangle of the reduced information matrix of z
    add_upper(info, total_scatter_, kz);
    add_upper(info, middle_scatter_, kz);
    add_upper(info, block_scatter_, kz);
    with_z_size([&](auto size) {
      constexpr int K = decltype(size)::value;
      for (int g = 0; g < groups_; ++g) {
        // The merge of total_ and block_ (Chan et al.): its rank-one term, accumulated without copying.
        const GroupMean& a = total_[g];
        const GroupMean& b = block_[g];
        out.rows += a.count + b.count;
        if (a.count == 0 || b.count == 0) continue;
        const Scalar na = static_cast<Scalar>(a.count);
        const Scalar nb = static_cast<Scalar>(b.count);
        add_rank_one<K>(info, b.mean - a.mean, na * nb / (na + nb));
      }
      // Group 0 has no free offset: its raw second moment is scatter + count * mean mean'.
      const GroupMean g0 = merged(0);
      add_rank_one<K>(info, g0.mean, static_cast<Scalar>(g0.count));
    });
    for (int g = 1; g < groups_; ++g) {
      if (total_[g].count + block_[g].count == 0) return out;  // mu for column g-1 not excited yet: kNotExcited
    }
    if (out.rows <= static_cast<std::uint32_t>(dim())) return out;

    NMat A = NMat::Zero();  // the full symmetric n x n block, from the upper triangle
    NVec r = NVec::Zero();
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i <= j; ++i) A(i, j) = A(j, i) = info(i, j);
      r(j) = info(j, n);
    }
    out.rcond = reciprocal_condition(A, n);
    SmallCholesky<Scalar, N> chol;
    if (!(out.rcond >= min_rcond()) || !chol.compute(A, n)) {
      out.status = Status::kIllConditioned;
      return out;
    }
    const NVec a = chol.solve(r);
    NMat A_inv = NMat::Zero();
    if (with_std_errors) {
      for (int k = 0; k < n; ++k) A_inv.col(k) = chol.solve(NVec::Unit(k));
    }
    for (int i = 0; i < n; ++i) out.theta(i) = a(i);
    for (int k = 0; k < n * m_; ++k) {
      const GroupMean gk = merged(k + 1);
      out.theta(n + k) = (gk.mean(n) - head_dot(gk.mean, a, n)) / w_(k);
    }
    out.status = out.theta.allFinite() ? Status::kOk : Status::kIllConditioned;
    if (!with_std_errors || out.status != Status::kOk) return out;

    const Scalar rss = std::fmax(info(n, n) - r.dot(a), Scalar(0));
    out.noise_variance = rss / static_cast<Scalar>(out.rows - static_cast<std::uint32_t>(dim()));
    for (int i = 0; i < n; ++i) out.std_error(i) = std::sqrt(out.noise_variance * A_inv(i, i));
    for (int k = 0; k < n * m_; ++k) {
      // var(mu_k) = sigma^2 [1/(count w^2) + (phibar/w)' A^-1 (phibar/w)]: group mean and within-group slope are
      // uncorrelated.
      const GroupMean gk = merged(k + 1);
      NVec h = NVec::Zero();
      for (int i = 0; i < n; ++i) h(i) = gk.mean(i) / w_(k);
      const Scalar var = out.noise_variance * (Scalar(1) / (static_cast<Scalar>(gk.count) * w_(k) * w_(k)) +
                                               h.dot(A_inv * h));
      out.std_error(n + k) = std::sqrt(var);
    }
    return out;
  }

 private:
  /// Calls f(std::integral_constant<int, n + 1>) for the run-time n: the kernels below are compiled per size.
  template <class F>
  void with_z_size(F&& f) const {
    dispatch(std::forward<F>(f), std::make_integer_sequence<int, N>{});
  }
  template <class F, int... I>
  void dispatch(F&& f, std::integer_sequence<int, I...> /*sizes*/) const {
    (void)((n_ == I + 1 ? (f(std::integral_constant<int, I + 2>{}), true) : false) || ...);
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

  // Chan et al.'s merge of group g's block into its total; the rank-one term goes into the total scatter.
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
      for (int i = 0; i <= n_; ++i) a.mean(i) += delta(i) * (nb / n);
      with_z_size([&](auto size) { add_rank_one<decltype(size)::value>(middle_scatter_, delta, na * nb / n); });
      a.count += b.count;
    }
    b = GroupMean{};
  }

  /// Count and mean of group g over all its rows (total and current block).
  GroupMean merged(int g) const {
    const GroupMean& a = total_[g];
    const GroupMean& b = block_[g];
    if (a.count == 0) return b;
    if (b.count == 0) return a;
    GroupMean out;
    out.count = a.count + b.count;
    const Scalar w = static_cast<Scalar>(b.count) / static_cast<Scalar>(out.count);
    out.mean = a.mean + (b.mean - a.mean) * w;
    return out;
  }

  static Scalar head_dot(const ZVec& z, const NVec& a, int n) {
    Scalar s = Scalar(0);
    for (int i = 0; i < n; ++i) s += z(i) * a(i);
    return s;
  }

  // info += s on the upper triangle of the leading k x k block (what triangularView<Upper>() += s computes).
  static void add_upper(ZMat& info, const ZMat& s, int k) {
    for (int j = 0; j < k; ++j) {
      for (int i = 0; i <= j; ++i) info(i, j) += s(i, j);
    }
  }

  // info += alpha v v' on the upper triangle of the leading K x K block, unrolled (solve() merges every group with
  // it: Cortex-M4F 2,680 -> 2,000 instructions per estimate at n = 2, m = 6).
  template <int K>
  static void add_rank_one(ZMat& info, const ZVec& v, Scalar alpha) {
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
      if (n != 2) return reciprocal_condition_spd<Scalar, N>(A, n);
      // Closed form for a symmetric 2x2: lambda = (tr -+ sqrt((a-d)^2 + 4b^2)) / 2.
      if (!std::isfinite(A(0, 0)) || !std::isfinite(A(0, 1)) || !std::isfinite(A(1, 1))) return Scalar(0);
      const Scalar half_tr = Scalar(0.5) * (A(0, 0) + A(1, 1));
      const Scalar half_gap = std::hypot(Scalar(0.5) * (A(0, 0) - A(1, 1)), A(0, 1));
      const Scalar hi = half_tr + half_gap;
      return hi > Scalar(0) ? std::fmax(half_tr - half_gap, Scalar(0)) / hi : Scalar(0);
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
