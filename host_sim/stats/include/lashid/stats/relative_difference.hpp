// Relative difference of two parameter vectors: how far an estimate is from a reference (the truth, the paper's
// numbers, another build of the same estimator).
#pragma once

#include <cmath>
#include <cstddef>
#include <span>

namespace lashid::sim::stats {

/// ||x - ref|| / ||ref|| (Euclidean norms); x and ref have the same length.
inline double relative_difference(std::span<const double> x, std::span<const double> ref) {
  double num = 0, den = 0;
  for (std::size_t k = 0; k < ref.size(); ++k) {
    num += (x[k] - ref[k]) * (x[k] - ref[k]);
    den += ref[k] * ref[k];
  }
  return std::sqrt(num / den);
}

}  // namespace lashid::sim::stats
