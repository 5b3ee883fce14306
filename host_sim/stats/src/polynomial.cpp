// Roots, stability and reflection of monic polynomials (polynomial.hpp).
#include "lashid/stats/polynomial.hpp"

#include <cmath>
#include <cstddef>
#include <utility>

#include <Eigen/Dense>

namespace lashid::sim::stats {

std::vector<std::complex<double>> polynomial_roots(const std::vector<double>& a) {
  const auto n = static_cast<Eigen::Index>(a.size());
  if (n == 0) return {};
  Eigen::MatrixXd companion = Eigen::MatrixXd::Zero(n, n);
  for (Eigen::Index k = 0; k < n; ++k) companion(0, k) = -a[static_cast<std::size_t>(k)];
  for (Eigen::Index k = 1; k < n; ++k) companion(k, k - 1) = 1.0;
  const Eigen::EigenSolver<Eigen::MatrixXd> solver(companion, false);
  std::vector<std::complex<double>> roots;
  roots.reserve(a.size());
  for (Eigen::Index k = 0; k < n; ++k) roots.push_back(solver.eigenvalues()(k));
  return roots;
}

std::vector<double> polynomial_from_roots(const std::vector<std::complex<double>>& roots) {
  std::vector<std::complex<double>> c{1.0};
  for (const auto& r : roots) {
    std::vector<std::complex<double>> next(c.size() + 1, 0.0);
    for (std::size_t k = 0; k < c.size(); ++k) {
      next[k] += c[k];
      next[k + 1] -= r * c[k];
    }
    c = std::move(next);
  }
  std::vector<double> a;
  a.reserve(roots.size());
  for (std::size_t k = 1; k < c.size(); ++k) a.push_back(c[k].real());
  return a;
}

bool is_stable(const std::vector<double>& a) {
  for (const auto& r : polynomial_roots(a)) {
    if (!(std::abs(r) < 1.0)) return false;
  }
  return true;
}

std::vector<double> reflected_into_unit_circle(const std::vector<double>& a) {
  std::vector<std::complex<double>> roots = polynomial_roots(a);
  bool reflected = false;
  for (auto& r : roots) {
    if (std::abs(r) > 1.0) {
      r = 1.0 / std::conj(r);
      reflected = true;
    }
  }
  return reflected ? polynomial_from_roots(roots) : a;
}

}  // namespace lashid::sim::stats
