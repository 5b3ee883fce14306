// The linear algebra of the joint model's fit (see joint_model_solve.hpp).
#include "joint_model_solve.hpp"

#include <algorithm>
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
    // Factorised in place (LLT<Ref>): a copy of ~360 x 360 less per solve.
    Eigen::MatrixXd scaled = scale.asDiagonal() * zx * scale.asDiagonal();
    const Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>> llt(scaled);
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
// Session 25, tuning seeds 1040-1239: at most 3 instead of 6, 1,174 of 1,200 single causes and 733 of 800 pairs
// against 1,171 and 730, and 10 % less time on pair 10827 (docs/diagnose.md, "Time"); on the fresh seeds
// 11250-11449, 1,906 of 2,000 against 1,909: kept for the time, not for accuracy. Most fits are inside a regime
// iteration or along a lambda path, where the next pass or lambda starts from this one's result: the steps not
// taken here can be taken there.
constexpr int kRankOneIterations = 3;
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
  // The kept columns are a (n), then per lag i the same kept border points (kept_k of them, c_0 first when kept:
  // excited_columns keeps or drops a point for every lag at once), then the rest. In these terms the step's
  // reduced columns are x = T' (full columns): full = T x - offset, where a product column (i, k) is
  // c_k b'_i + b_i c'_k (k != 0) and every other column is itself. T has a block structure, so
  // M = T' zx T and g = T' (zy + zx offset) are a few matrix products on zx's blocks (an entry-by-entry
  // assembly was half of a diagnosis' time in this function).
  const Eigen::Index extras = cols - first_extra;
  const Eigen::Index K = static_cast<Eigen::Index>(keep.size());
  const Eigen::Index kept_k = (K - n - extras) / n;
  const bool c0_kept = kept_k > 0 && keep[static_cast<std::size_t>(n)] == n;
  const auto block = [&](int i) { return static_cast<Eigen::Index>(n) + i * kept_k; };  // lag i's first kept column
  const Eigen::Index first_c = c0_kept ? 1 : 0;  // within a lag block, the first column with a free c'
  Eigen::VectorXd c_kept(kept_k);
  const Eigen::Index extra_at = block(n);  // position of the first extra column among the kept ones
  int steps = 0;
  for (int iteration = 0; iteration < kRankOneIterations; ++iteration) {
    for (Eigen::Index q = 0; q < kept_k; ++q) c_kept(q) = c(keep[static_cast<std::size_t>(block(0) + q)] - n);
    // W = zx T, one pass over the product columns (each column of zx feeds both of its reduced columns while it
    // is in cache), and zx offset from it: offset = b_i c_k on every product column with a free c'_k, so
    // zx offset = sum_i b_i (W_(b'_i) - c_0 zx_(i, 0)).
    // Each sum's first term is assigned rather than added to a zeroed column (the same values: 0 + x is x; the
    // zeroing was a tenth of this function's time).
    Eigen::MatrixXd W(K, R);
    W.leftCols(n) = zx.leftCols(n);
    if (kept_k == 0) W.middleCols(n, n).setZero();
    for (int i = 0; i < n; ++i) {
      for (Eigen::Index q = 0; q < kept_k; ++q) {
        const auto column = zx.col(block(i) + q);
        if (q == 0) {
          W.col(n + i) = c_kept(q) * column;
        } else {
          W.col(n + i) += c_kept(q) * column;
        }
        if (q < first_c) continue;
        if (i == 0) {
          W.col(2 * n + q - first_c) = b(i) * column;
        } else {
          W.col(2 * n + q - first_c) += b(i) * column;
        }
      }
    }
    W.rightCols(extras) = zx.rightCols(extras);
    Eigen::VectorXd rhs_full = zy;
    for (int i = 0; i < n; ++i) {
      rhs_full += b(i) * W.col(n + i);
      if (c0_kept) rhs_full -= (b(i) * c_kept(0)) * zx.col(block(i));
    }
    // M = T' W and g = T' rhs_full, the same blocks by rows.
    Eigen::MatrixXd M(R, R);
    Eigen::VectorXd g(R);
    M.topRows(n) = W.topRows(n);
    g.head(n) = rhs_full.head(n);
    for (int i = 0; i < n; ++i) {
      M.row(n + i).noalias() = c_kept.transpose() * W.middleRows(block(i), kept_k);
      g(n + i) = c_kept.dot(rhs_full.segment(block(i), kept_k));
      if (i == 0) {
        M.middleRows(2 * n, kept_c) = b(i) * W.middleRows(block(i) + first_c, kept_c);
        g.segment(2 * n, kept_c) = b(i) * rhs_full.segment(block(i) + first_c, kept_c);
      } else {
        M.middleRows(2 * n, kept_c) += b(i) * W.middleRows(block(i) + first_c, kept_c);
        g.segment(2 * n, kept_c) += b(i) * rhs_full.segment(block(i) + first_c, kept_c);
      }
    }
    M.bottomRows(extras) = W.bottomRows(extras);
    g.tail(extras) = rhs_full.segment(extra_at, extras);
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
