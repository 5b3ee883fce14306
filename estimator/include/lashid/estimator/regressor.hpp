// The regressor Phi(t) of (3.19b) built from O(n) history of the centred signals (3.9a)/(4.3):
//   Phi(t) = [-y~(t-1) .. -y~(t-n),  v~(t-1)P_1(v~(t-1)) .. v~(t-n)P_1(v~(t-n)),  ...,  .. v~(t-n)P_m(v~(t-n))]
//   Theta  = [a_1 .. a_n, mu_11 .. mu_n1, ..., mu_1m .. mu_nm],   mu_ij = b_i c_j.
// Column of mu_ij (1-based i, j) in Theta: n + (j-1) n + (i-1).
//
// Sparse view: on the design, v~(t-i) is 0 or some W_l and P_j(W_l) = delta_jl, so the input part of Phi(t) has a
// non-zero only at column (l, i), of value W_l; with the pulse spacing of (3.25) at most one lag holds a pulse,
// hence at most one non-zero input entry per row. GroupedLeastSquares exploits this.
// N and M are capacities; the builder uses the order n <= N and the basis' m <= M given at construction, and the
// layout above with those n, m (the first n + n m entries of a dense row).
#pragma once

#include <cstddef>
#include <cstdint>

#include <Eigen/Core>

#include "lashid/estimator/lagrange.hpp"
#include "lashid/estimator/order_dispatch.hpp"
#include "lashid/estimator/status.hpp"

namespace lashid::est {

template <class Scalar, int N, int M>
struct SparseRegressor {
  Eigen::Matrix<Scalar, N, 1> phi_y;  ///< [-y~(t-1) .. -y~(t-n)] in the first n entries
  int input_column = -1;              ///< index k in 0..n*m-1 of the input entry among the mu's, -1 if none
  Scalar input_value = Scalar(0);     ///< its value W_l
};

template <class Scalar, int N, int M>
class RegressorBuilder {
 public:
  static constexpr int kDim = N + N * M;
  using Dense = Eigen::Matrix<Scalar, kDim, 1>;
  using Basis = LagrangeBasis<Scalar, M>;

  /// `n` in [1, N] (clamped), `m` in [1, M] (clamped by the basis).
  explicit RegressorBuilder(const typename Basis::Nodes& W, int n = N, int m = M)
      : basis_(W, m), n_(n < 1 ? 1 : (n > N ? N : n)) {}

  int order() const { return n_; }
  int points() const { return basis_.size(); }
  /// Entries of Theta (and of a dense row) at this n, m.
  int dim() const { return n_ + n_ * basis_.size(); }

  /// True once n samples of history exist, i.e. Phi(t) is defined for the next sample.
  bool ready() const { return filled_ >= n_; }

  /// Appends the centred sample (v~(t), y~(t)) after Phi(t) has been used.
  void push(Scalar v_tilde, Scalar y_tilde) {
    with_order<N>(n_, [&](auto order) { push_n<decltype(order)::value>(v_tilde, y_tilde); });
  }
  /// push() for the order Nn = n, known at compile time (the caller dispatched on n already).
  template <int Nn>
  void push_n(Scalar v_tilde, Scalar y_tilde) {
    static_assert(Nn >= 1 && Nn <= N);
#pragma GCC unroll 8
    for (int i = Nn - 1; i > 0; --i) {
      v_(i) = v_(i - 1);
      y_(i) = y_(i - 1);
      class_[i] = class_[i - 1];
    }
    v_(0) = v_tilde;
    y_(0) = y_tilde;
    class_[0] = basis_.classify(v_tilde);
    if (filled_ < Nn) ++filled_;
  }

  void reset() { filled_ = 0; }

  /// basis().classify() of the newest centred input, as computed by push() (meaningful after the first push()).
  int newest_class() const { return class_[0]; }

  /// Sparse Phi(t) for the next sample. kInputOffDesign when a lag is off the design or two lags hold pulses.
  Status sparse(SparseRegressor<Scalar, N, M>& row) const {
    Status s = Status::kNotExcited;
    with_order<N>(n_, [&](auto order) { s = sparse_n<decltype(order)::value>(row); });
    return s;
  }
  /// sparse() for the order Nn = n, known at compile time.
  template <int Nn>
  Status sparse_n(SparseRegressor<Scalar, N, M>& row) const {
    static_assert(Nn >= 1 && Nn <= N);
    if (filled_ < Nn) return Status::kNotExcited;
    row.input_column = -1;
    row.input_value = Scalar(0);
#pragma GCC unroll 8  // rolled, this loop over the n lags costs ~10 more instructions per sample (Cortex-M4F)
    for (int i = 0; i < Nn; ++i) {
      row.phi_y(i) = -y_(i);
      const int l = class_[i];
      if (l == Basis::kOffDesign) return Status::kInputOffDesign;
      if (l == Basis::kZero) continue;
      if (row.input_column >= 0) return Status::kInputOffDesign;
      row.input_column = l * Nn + i;
      row.input_value = basis_.nodes()(l);
    }
    return Status::kOk;
  }

  /// Dense Phi(t) of (3.19b), evaluating the Lagrange polynomials (valid for any input, on the design or not).
  /// The first dim() entries; the rest are zero.
  Status dense(Dense& phi) const {
    if (!ready()) return Status::kNotExcited;
    phi.setZero();
    for (int i = 0; i < n_; ++i) phi(i) = -y_(i);
    for (int j = 0; j < basis_.size(); ++j) {
      for (int i = 0; i < n_; ++i) phi(n_ + j * n_ + i) = v_(i) * basis_.P(j, v_(i));
    }
    return Status::kOk;
  }

  const Basis& basis() const { return basis_; }

 private:
  Basis basis_;
  int n_;
  Eigen::Matrix<Scalar, N, 1> v_ = Eigen::Matrix<Scalar, N, 1>::Zero();  // v_(i) = v~(t-1-i) once pushed
  Eigen::Matrix<Scalar, N, 1> y_ = Eigen::Matrix<Scalar, N, 1>::Zero();
  int class_[static_cast<std::size_t>(N)] = {};
  int filled_ = 0;
};

}  // namespace lashid::est
