// Recovery of b_i, c_j and the border points from Theta, (3.20)-(3.23) for the DIS and Section 4 / Remark 3a for
// the AIS. With s = F~(W_1) = -1 (DIS) or +1 (AIS):
//   c_1 = s / W_1,  b_i = mu_i1 / c_1 = s mu_i1 W_1,                         (3.20a), (3.22a), Remark 3a
//   c_j = sum_i b_i mu_ij / sum_i b_i^2   (j = 2..m),                        (3.22b)
//   F(V_j) = c_j W_j + A(1)/B(1) ybar_0,                                     (3.23)
// where A(1)/B(1) ybar_0 estimates u_M (DIS) or u_m (AIS), the operator's output at the held level (3.7).
#pragma once

#include <cmath>

#include <Eigen/Core>

#include "lashid/estimator/design.hpp"
#include "lashid/estimator/least_squares.hpp"

namespace lashid::est {

/// N and M are capacities: a, b hold n entries and c, F m entries (n = ls.n, m = ls.m), then zeros.
template <class Scalar, int N, int M>
struct SchemeEstimate {
  Scheme scheme = Scheme::kDescending;
  Eigen::Matrix<Scalar, N, 1> a = Eigen::Matrix<Scalar, N, 1>::Zero();
  Eigen::Matrix<Scalar, N, 1> b = Eigen::Matrix<Scalar, N, 1>::Zero();
  Eigen::Matrix<Scalar, M, 1> c = Eigen::Matrix<Scalar, M, 1>::Zero();
  Eigen::Matrix<Scalar, M, 1> F_centered = Eigen::Matrix<Scalar, M, 1>::Zero();  ///< F~(W_j) = c_j W_j
  Eigen::Matrix<Scalar, M, 1> F = Eigen::Matrix<Scalar, M, 1>::Zero();           ///< F(V_j), scaling (3.11c)
  Scalar ybar0 = Scalar(0);         ///< step-experiment mean (3.7)
  Scalar held_output = Scalar(0);   ///< A(1)/B(1) ybar0: u_M (DIS) or u_m (AIS)
  LsSolution<Scalar, N, M> ls;      ///< Theta and its diagnostics
  Status status = Status::kNotExcited;
};

/// Fills a, b, c, F of `out` from Theta (out.ls.theta, of order out.ls.n) and ybar0 (out.ybar0). Only the first n
/// (a, b) and m (c, F) entries are written: the firmware recovers into the same estimate every pulse period.
template <class Scalar, int N, int M>
Status recover(const ExperimentDesign<Scalar, M>& design, SchemeEstimate<Scalar, N, M>& out) {
  const auto& theta = out.ls.theta;
  const int n = out.ls.n;
  const int m = design.m;
  if (n < 1 || n > N || m < 1 || m > M || out.ls.m != m) return Status::kOrderOutOfRange;
  const Scalar held = design.held_level();
  const auto mu = [&](int i, int j) { return theta(n + j * n + i); };  // 0-based i (lag), j (point)

  out.scheme = design.scheme;
  out.c(0) = design.scaled_first_point() / (design.V(0) - held);
  Scalar bb = Scalar(0);
  Scalar B1 = Scalar(0);
  Scalar A1 = Scalar(1);
  for (int i = 0; i < n; ++i) {
    out.a(i) = theta(i);
    out.b(i) = mu(i, 0) / out.c(0);
    bb += out.b(i) * out.b(i);
    B1 += out.b(i);
    A1 += out.a(i);
  }
  if (!(bb > Scalar(0)) || !(std::fabs(B1) > Scalar(0)) || !std::isfinite(bb)) return Status::kDegenerateGain;
  for (int j = 1; j < m; ++j) {
    Scalar num = Scalar(0);
    for (int i = 0; i < n; ++i) num += out.b(i) * mu(i, j);
    out.c(j) = num / bb;
  }
  out.held_output = A1 / B1 * out.ybar0;
  bool finite = std::isfinite(out.held_output);
  for (int j = 0; j < m; ++j) {
    out.F_centered(j) = out.c(j) * (design.V(j) - held);
    out.F(j) = out.F_centered(j) + out.held_output;
    finite = finite && std::isfinite(out.F(j));
  }
  return finite ? Status::kOk : Status::kDegenerateGain;
}

}  // namespace lashid::est
