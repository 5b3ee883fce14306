// The linear algebra of the joint model's fit (see joint_model_solve.hpp).
#include "joint_model_solve.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>

#include <fmt/format.h>

namespace lashid::sim::detail {

std::optional<Eigen::VectorXd> solve_normal_equations(const Eigen::MatrixXd& zx, const Eigen::VectorXd& zy,
                                                      bool instrumental, std::string& failure) {
  const auto kept = static_cast<int>(zx.cols());
  if (!instrumental) {
    // Cholesky (blocked: the finer tables' 300-odd columns made the unblocked pivoted LDL' a quarter of a
    // diagnosis) of the scaled (unit-diagonal) matrix. A pivot, the squared diagonal of L, is the part of its
    // column not explained by the columns before it: below 1e-12 the column is a combination of the others (in
    // X's terms, a singular value below about 1e-6 of the largest).
    const Eigen::VectorXd scale = zx.diagonal().cwiseSqrt().cwiseInverse();
    const Eigen::MatrixXd scaled = scale.asDiagonal() * zx * scale.asDiagonal();
    const Eigen::LLT<Eigen::MatrixXd> llt(scaled);
    const Eigen::VectorXd pivots = llt.matrixLLT().diagonal().array().square();
    const auto independent = static_cast<int>((pivots.array() > 1e-12).count());
    if (llt.info() != Eigen::Success || independent < kept) {
      failure = fmt::format("the regression is rank deficient ({} of {} columns independent): "
                            "the experiments do not excite every border point",
                            independent, kept);
      return std::nullopt;
    }
    return Eigen::VectorXd(scale.asDiagonal() * llt.solve(Eigen::VectorXd(scale.asDiagonal() * zy)));
  }
  const Eigen::PartialPivLU<Eigen::MatrixXd> lu(zx);
  if (!(lu.rcond() > 1e-13)) {
    failure = "the instrumental-variable system is singular";
    return std::nullopt;
  }
  return Eigen::VectorXd(lu.solve(zy));
}

// Gauss-Newton steps of the rank-1 least squares: at most this many, stopping earlier when one gains less than
// kRankOneTolerance in likelihood-ratio terms (N ln(RSS_before / RSS_after)), far below any threshold the diagnosis
// uses. Measured on the tuning seeds 1000-1039 (curved borders): up to 20 steps (5.4 on average in the slowest
// diagnosis) gave 233 of 240 single causes and 142 of 160 pairs, slowest 2.1 s; at most 6, 233 and 141, 1.7 s.
constexpr int kRankOneIterations = 6;
constexpr int kRankOneHalvings = 4;
constexpr double kRankOneTolerance = 0.01;

// Least squares restricted to rank one (the products b_i c_k = b_i c_k), from the unrestricted solution or a rank-1
// warm start: Gauss-Newton on the normal equations. Linearised at (b, c), the products are b'_i c_k + b_i c'_k -
// b_i c_k, linear in (a, b', c', the rest), so each step is one linear least-squares problem whose normal equations
// are sums of the full ones' entries (c'_0 stays fixed: the scale of b c' is free). A step that does not lower the
// objective is halved (up to kRankOneHalvings times); if none of them does, or a step's system is singular, the
// iteration ends at the best point so far. The paper's over-parametrisation (3.21) then its best rank-1
// factorisation is not the least-squares rank-1 model once the products have many border columns (n >= 2 with the
// finer tables): its RSS is that of n free borders, and the factorised model's can be far larger.
int refine_rank_one(const Eigen::MatrixXd& zx, const Eigen::VectorXd& zy, const std::vector<Eigen::Index>& keep,
                    int n, int P, double yy, std::size_t rows, Eigen::VectorXd& theta) {
  const double relative_tolerance = kRankOneTolerance / static_cast<double>(rows);
  const Eigen::Index cols = theta.size();
  const auto first_extra = static_cast<Eigen::Index>(n + n * P);
  Eigen::MatrixXd products(n, P);
  for (int i = 0; i < n; ++i) products.row(i) = theta.segment(n + i * P, P).transpose();
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(products, Eigen::ComputeThinU | Eigen::ComputeThinV);
  Eigen::VectorXd b = svd.singularValues()(0) * svd.matrixU().col(0);
  Eigen::VectorXd c = svd.matrixV().col(0);
  // Reduced columns: a (n), b' (n), c'_k for every kept k but 0, the rest.
  std::vector<int> c_index(static_cast<std::size_t>(P), -1);
  int kept_c = 0;
  for (Eigen::Index j : keep) {
    const auto k = static_cast<std::size_t>((j - n) % P);
    if (j >= n && j < first_extra && k != 0 && c_index[k] < 0) c_index[k] = kept_c++;
  }
  const Eigen::Index R = 2 * n + kept_c + (cols - first_extra);
  const auto x_of = [&](const Eigen::VectorXd& th) {
    Eigen::VectorXd x(static_cast<Eigen::Index>(keep.size()));
    for (std::size_t q = 0; q < keep.size(); ++q) x(static_cast<Eigen::Index>(q)) = th(keep[q]);
    return x;
  };
  const auto objective = [&](const Eigen::VectorXd& th) {
    const Eigen::VectorXd x = x_of(th);
    return x.dot(zx * x) - 2.0 * x.dot(zy);
  };
  const auto assemble = [&](const Eigen::VectorXd& base, const Eigen::VectorXd& bb, const Eigen::VectorXd& cc) {
    Eigen::VectorXd th = base;
    for (int i = 0; i < n; ++i) th.segment(n + i * P, P) = bb(i) * cc;
    return th;
  };
  // Stop when a step lowers the RSS by less than relative_tolerance of the starting point's (in likelihood-ratio
  // terms, N ln(RSS_before / RSS_after) < N relative_tolerance).
  const double tolerance = relative_tolerance * std::max(yy + objective(theta), 0.0);
  Eigen::VectorXd best = assemble(theta, b, c);
  double best_objective = objective(best);
  // Each kept full column q is sum_e f * x(r) over at most two reduced columns, minus offset(q).
  struct Term {
    Eigen::Index r;
    double f;
  };
  std::vector<std::array<Term, 2>> terms(keep.size());
  std::vector<int> count(keep.size());
  int steps = 0;
  for (int iteration = 0; iteration < kRankOneIterations; ++iteration) {
    Eigen::VectorXd offset = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(keep.size()));
    for (std::size_t q = 0; q < keep.size(); ++q) {
      const Eigen::Index j = keep[q];
      count[q] = 1;
      if (j < n) {
        terms[q][0] = {j, 1.0};
      } else if (j < first_extra) {
        const Eigen::Index i = (j - n) / P, k = (j - n) % P;
        terms[q][0] = {n + i, c(k)};
        if (k != 0) {
          terms[q][1] = {2 * n + c_index[static_cast<std::size_t>(k)], b(i)};
          count[q] = 2;
          offset(static_cast<Eigen::Index>(q)) = b(i) * c(k);
        }
      } else {
        terms[q][0] = {2 * n + kept_c + (j - first_extra), 1.0};
      }
    }
    // T' zx T x = T' (zy + zx offset): W = zx T, then M = T' W, each a column at a time.
    const Eigen::VectorXd rhs_full = zy + zx * offset;
    Eigen::MatrixXd W = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(keep.size()), R);
    for (std::size_t q = 0; q < keep.size(); ++q) {
      for (int e = 0; e < count[q]; ++e) {
        const Term t = terms[q][static_cast<std::size_t>(e)];
        W.col(t.r) += t.f * zx.col(static_cast<Eigen::Index>(q));
      }
    }
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(R, R);
    Eigen::VectorXd g = Eigen::VectorXd::Zero(R);
    for (std::size_t q = 0; q < keep.size(); ++q) {
      for (int e = 0; e < count[q]; ++e) {
        const Term t = terms[q][static_cast<std::size_t>(e)];
        g(t.r) += t.f * rhs_full(static_cast<Eigen::Index>(q));
      }
    }
    for (Eigen::Index col = 0; col < R; ++col) {
      const auto w = W.col(col);
      auto m = M.col(col);
      for (std::size_t q = 0; q < keep.size(); ++q) {
        const double wq = w(static_cast<Eigen::Index>(q));
        for (int e = 0; e < count[q]; ++e) {
          const Term t = terms[q][static_cast<std::size_t>(e)];
          m(t.r) += t.f * wq;
        }
      }
    }
    std::string failure;
    const std::optional<Eigen::VectorXd> x = solve_normal_equations(M, g, false, failure);
    if (!x) break;  // keep the best model so far (the factorisation's, if this was the first step)
    Eigen::VectorXd full = best;
    for (int i = 0; i < n; ++i) full(i) = (*x)(i);
    for (Eigen::Index j = first_extra; j < cols; ++j) full(j) = (*x)(2 * n + kept_c + (j - first_extra));
    const Eigen::VectorXd b_full = x->segment(n, n);
    Eigen::VectorXd c_full = c;
    for (int k = 1; k < P; ++k) {
      if (c_index[static_cast<std::size_t>(k)] >= 0) c_full(k) = (*x)(2 * n + c_index[static_cast<std::size_t>(k)]);
    }
    // Backtracking: from a factorisation far from the optimum the full step can overshoot (the objective rose on
    // the first step in most fits of curved tuning seed 1136, n = 3, leaving an RSS 20 to 50 times the optimum's).
    bool improved = false;
    double step = 1.0;
    for (int halving = 0; halving <= kRankOneHalvings && !improved; ++halving, step *= 0.5) {
      const Eigen::VectorXd b_next = b + step * (b_full - b);
      const Eigen::VectorXd c_next = c + step * (c_full - c);
      Eigen::VectorXd next = assemble(best + step * (full - best), b_next, c_next);
      const double now = objective(next);
      if (!(now < best_objective)) continue;
      improved = true;
      ++steps;
      const bool converged = best_objective - now <= tolerance;
      best = std::move(next);
      best_objective = now;
      b = b_next;
      c = c_next;
      if (converged) iteration = kRankOneIterations;
    }
    if (!improved) break;
  }
  theta = best;
  return steps;
}

}  // namespace lashid::sim::detail
