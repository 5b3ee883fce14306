// Lagrange basis of (3.14b): P_j(w) = prod_{i != j} (w - W_i) / (W_j - W_i), so that P_j(W_i) = delta_ij (3.15).
// The regression (3.19) only holds while the centred input takes values in {0, W_1..W_m}; classify() maps a
// centred input to that set, which is what lets the recursive estimator use the sparse form of the regressor.
// M is the capacity; the basis uses the first m nodes (m = M unless given).
#pragma once

#include <cmath>
#include <limits>

#include <Eigen/Core>

namespace lashid::est {

/// The relative resolution of LagrangeBasis::classify: a sample matches a node within kLevelResolution x max |W_j|.
template <class Scalar>
inline constexpr Scalar kLevelResolution = Scalar(64) * std::numeric_limits<Scalar>::epsilon();

template <class Scalar, int M>
class LagrangeBasis {
 public:
  using Nodes = Eigen::Matrix<Scalar, M, 1>;
  static constexpr int kZero = -1;       ///< classify(): the input is at the held level (w = 0)
  static constexpr int kOffDesign = -2;  ///< classify(): neither 0 nor any W_j

  explicit LagrangeBasis(const Nodes& W, int m = M) : W_(W), m_(m < 1 ? 1 : (m > M ? M : m)) {
    Scalar scale = Scalar(0);
    for (int j = 0; j < m_; ++j) scale = std::fmax(scale, std::fabs(W_(j)));
    // Relative tolerance for matching a sample to a node: inputs that went through text or float conversion still
    // match, distinct nodes (validated strictly ordered) do not, unless closer than this.
    tolerance_ = scale * kLevelResolution<Scalar>;
  }

  /// P_j(w), j = 0..m-1 (the paper's j = 1..m).
  Scalar P(int j, Scalar w) const {
    Scalar p = Scalar(1);
    for (int i = 0; i < m_; ++i) {
      if (i != j) p *= (w - W_(i)) / (W_(j) - W_(i));
    }
    return p;
  }

  /// Index j (0-based) with w == W_j, kZero when w == 0, kOffDesign otherwise.
  int classify(Scalar w) const {
    if (std::fabs(w) <= tolerance_) return kZero;
    // Unrolled to the capacity M, leaving at m: the rolled loop costs about 8 more instructions per sample on the
    // Cortex-M4F (docs/on-target-cost.md).
#pragma GCC unroll 16
    for (int j = 0; j < M; ++j) {
      if (j >= m_) break;
      if (std::fabs(w - W_(j)) <= tolerance_) return j;
    }
    return kOffDesign;
  }

  const Nodes& nodes() const { return W_; }
  int size() const { return m_; }

 private:
  Nodes W_;
  int m_;
  Scalar tolerance_;
};

}  // namespace lashid::est
