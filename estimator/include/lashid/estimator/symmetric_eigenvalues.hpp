// Eigenvalues of a small symmetric matrix by the cyclic Jacobi method (Golub & Van Loan, Matrix Computations,
// 4th ed., Sec. 8.5.2): rotations zero the off-diagonal entries one by one until they are negligible. Chosen over
// Eigen's SelfAdjointEigenSolver::compute(), whose Householder tridiagonalisation links malloc (blocked updates),
// and because Jacobi is accurate to a small multiple of eps * ||A|| for every eigenvalue, which is what a condition
// number check needs. Fixed-size, heap-free, O(n^3) per sweep, a handful of sweeps. D is the capacity; the routine
// works on the leading n x n block (n = D unless given), the firmware's run-time order.
#pragma once

#include <cmath>

#include <Eigen/Core>

namespace lashid::est {

/// The n eigenvalues of the leading n x n block of A, ascending, in the first n entries (the rest zero).
template <class Scalar, int D>
Eigen::Matrix<Scalar, D, 1> symmetric_eigenvalues(Eigen::Matrix<Scalar, D, D> A, int order = D, int max_sweeps = 32) {
  const int n = order < D ? order : D;  // the explicit bound also spares GCC a false -Warray-bounds
  const Scalar eps = Eigen::NumTraits<Scalar>::epsilon();
  for (int sweep = 0; sweep < max_sweeps; ++sweep) {
    Scalar off = Scalar(0);
    Scalar diagonal = Scalar(0);
    for (int p = 0; p < n; ++p) {
      diagonal += A(p, p) * A(p, p);
      for (int q = p + 1; q < n; ++q) off += A(p, q) * A(p, q);
    }
    if (!(off > eps * eps * (diagonal + Scalar(2) * off))) break;  // off-diagonal negligible; also stops on NaN
    for (int p = 0; p < n - 1; ++p) {
      for (int q = p + 1; q < n; ++q) {
        if (A(p, q) == Scalar(0)) continue;
        // Rotation in the (p, q) plane that zeroes A(p, q): t = tan(angle), the smaller root of t^2 + 2 theta t = 1.
        const Scalar theta = (A(q, q) - A(p, p)) / (Scalar(2) * A(p, q));
        const Scalar t = (theta >= Scalar(0) ? Scalar(1) : Scalar(-1)) /
                         (std::fabs(theta) + std::sqrt(Scalar(1) + theta * theta));
        const Scalar c = Scalar(1) / std::sqrt(Scalar(1) + t * t);
        const Scalar s = t * c;
        for (int k = 0; k < n; ++k) {  // A <- A J (columns p, q)
          const Scalar akp = A(k, p);
          const Scalar akq = A(k, q);
          A(k, p) = c * akp - s * akq;
          A(k, q) = s * akp + c * akq;
        }
        for (int k = 0; k < n; ++k) {  // A <- J' A (rows p, q)
          const Scalar apk = A(p, k);
          const Scalar aqk = A(q, k);
          A(p, k) = c * apk - s * aqk;
          A(q, k) = s * apk + c * aqk;
        }
      }
    }
  }
  Eigen::Matrix<Scalar, D, 1> ev = Eigen::Matrix<Scalar, D, 1>::Zero();
  for (int i = 0; i < n; ++i) ev(i) = A(i, i);
  // Ascending order (insertion sort: n is small).
  for (int i = 1; i < n; ++i) {
    const Scalar x = ev(i);
    int j = i - 1;
    while (j >= 0 && ev(j) > x) {
      ev(j + 1) = ev(j);
      --j;
    }
    ev(j + 1) = x;
  }
  return ev;
}

/// Reciprocal 2-norm condition number of a symmetric positive semi-definite matrix (its leading n x n block, n >= 1);
/// 0 if singular or not finite.
template <class Scalar, int D>
Scalar reciprocal_condition_spd(const Eigen::Matrix<Scalar, D, D>& A, int order = D) {
  const int n = order < D ? order : D;
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      if (!std::isfinite(A(i, j))) return Scalar(0);
    }
  }
  const Eigen::Matrix<Scalar, D, 1> ev = symmetric_eigenvalues<Scalar, D>(A, n);
  if (!(ev(n - 1) > Scalar(0))) return Scalar(0);
  return std::fmax(ev(0), Scalar(0)) / ev(n - 1);
}

}  // namespace lashid::est
