// Cholesky factorisation A = L L' of a small symmetric positive definite matrix whose size n is chosen at run time
// within a fixed capacity D (the firmware's model order): fixed-size storage, heap-free, n^3/6 multiply-adds. One
// routine for every n keeps the firmware image small, where Eigen's fixed-size LDLT would be compiled once per n
// (docs/on-target-cost.md). Called after the condition number was checked (GroupedLeastSquares::solve), so a
// non-positive pivot means a rounding breakdown: reported as failure, never the square root of a negative number.
#pragma once

#include <cmath>

#include <Eigen/Core>

namespace lashid::est {

template <class Scalar, int D>
class SmallCholesky {
 public:
  using Matrix = Eigen::Matrix<Scalar, D, D>;
  using Vector = Eigen::Matrix<Scalar, D, 1>;

  /// Factorises the leading n x n block of A (its lower triangle is read). False if a pivot is not positive.
  bool compute(const Matrix& A, int order) {
    const int n = order < D ? order : D;  // the explicit bound also spares GCC a false -Warray-bounds at D = 1
    n_ = n;
    for (int j = 0; j < n; ++j) {
      Scalar d = A(j, j);
      for (int k = 0; k < j; ++k) d -= L_(j, k) * L_(j, k);
      if (!(d > Scalar(0))) return false;  // also catches NaN
      L_(j, j) = std::sqrt(d);
      for (int i = j + 1; i < n; ++i) {
        Scalar x = A(i, j);
        for (int k = 0; k < j; ++k) x -= L_(i, k) * L_(j, k);
        L_(i, j) = x / L_(j, j);
      }
    }
    return true;
  }

  /// x with A x = b in the leading n entries (the others are not touched).
  void solve_in_place(Vector& x) const {
    const int n = n_ < D ? n_ : D;
    for (int i = 0; i < n; ++i) {  // L z = b
      Scalar s = x(i);
      for (int k = 0; k < i; ++k) s -= L_(i, k) * x(k);
      x(i) = s / L_(i, i);
    }
    for (int i = n - 1; i >= 0; --i) {  // L' x = z
      Scalar s = x(i);
      for (int k = i + 1; k < n; ++k) s -= L_(k, i) * x(k);
      x(i) = s / L_(i, i);
    }
  }

 private:
  Matrix L_ = Matrix::Zero();
  int n_ = 0;
};

}  // namespace lashid::est
