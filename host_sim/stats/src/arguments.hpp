// Argument checks and sums shared by the sources of the stats layer (not installed: src/ only). Every check throws
// std::invalid_argument("lashid::sim::stats::<function>: <what is wrong>").
#pragma once

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace lashid::sim::stats::detail {

[[noreturn]] inline void fail(const std::string& function, const std::string& message) {
  throw std::invalid_argument("lashid::sim::stats::" + function + ": " + message);
}

inline void require_not_nan(const char* function, const char* name, double value) {
  if (std::isnan(value)) fail(function, fmt::format("{} is NaN", name));
}

inline void require_positive_finite(const char* function, const char* name, double value) {
  if (!std::isfinite(value) || value <= 0.0) {
    fail(function, fmt::format("{} must be finite and > 0, got {}", name, value));
  }
}

inline void require_finite_samples(const char* function, const char* name, std::span<const double> x) {
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (!std::isfinite(x[i])) fail(function, fmt::format("{}[{}] is not finite ({})", name, i, x[i]));
  }
}

inline void require_min_size(const char* function, const char* name, std::span<const double> x,
                             std::size_t min_size) {
  if (x.size() < min_size) {
    fail(function, fmt::format("{} needs at least {} samples, got {}", name, min_size, x.size()));
  }
}

inline void require_not_constant(const char* function, const char* name, std::span<const double> x) {
  const auto [lowest, highest] = std::minmax_element(x.begin(), x.end());
  if (*lowest == *highest) {
    fail(function, fmt::format("{} has zero variance (all {} samples equal {})", name, x.size(), *lowest));
  }
}

inline double mean(std::span<const double> x) {
  double sum = 0.0;
  for (const double v : x) sum += v;
  return sum / static_cast<double>(x.size());
}

// x - mean(x).
inline std::vector<double> deviations(std::span<const double> x) {
  const double m = mean(x);
  std::vector<double> d(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) d[i] = x[i] - m;
  return d;
}

inline double sum_of_squares(const std::vector<double>& d) {
  double s = 0.0;
  for (const double v : d) s += v * v;
  return s;
}

}  // namespace lashid::sim::stats::detail
