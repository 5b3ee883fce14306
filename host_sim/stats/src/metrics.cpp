// Fit percentage and median: see metrics.hpp.
#include "lashid/stats/metrics.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

#include "arguments.hpp"

namespace lashid::sim::stats {

using detail::fail;

double fit_percent(std::span<const double> measured, std::span<const double> simulated) {
  constexpr const char* function = "fit_percent";
  if (measured.size() != simulated.size()) {
    fail(function, fmt::format("measured and simulated must have equal lengths, got {} and {}", measured.size(),
                               simulated.size()));
  }
  detail::require_min_size(function, "measured", measured, 2);
  detail::require_finite_samples(function, "measured", measured);
  detail::require_finite_samples(function, "simulated", simulated);
  detail::require_not_constant(function, "measured", measured);
  const double norm_about_mean = std::sqrt(detail::sum_of_squares(detail::deviations(measured)));
  if (!(norm_about_mean > 0.0)) fail(function, "measured has zero variance");
  double error = 0.0;
  for (std::size_t i = 0; i < measured.size(); ++i) {
    const double d = measured[i] - simulated[i];
    error += d * d;
  }
  return 100.0 * (1.0 - std::sqrt(error) / norm_about_mean);
}

double median(std::span<const double> x) {
  constexpr const char* function = "median";
  detail::require_min_size(function, "x", x, 1);
  detail::require_finite_samples(function, "x", x);
  std::vector<double> values(x.begin(), x.end());
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  const double upper = *middle;
  if (values.size() % 2 == 1) return upper;
  // After the selection every value before `middle` is <= upper: the lower middle value is their maximum.
  const double lower = *std::max_element(values.begin(), middle);
  return 0.5 * (lower + upper);
}

double relative_difference(std::span<const double> x, std::span<const double> ref) {
  if (x.size() != ref.size()) {
    fail("relative_difference", fmt::format("x and ref must have equal lengths, got {} and {}", x.size(), ref.size()));
  }
  double num = 0, den = 0;
  for (std::size_t k = 0; k < ref.size(); ++k) {
    num += (x[k] - ref[k]) * (x[k] - ref[k]);
    den += ref[k] * ref[k];
  }
  // A zero reference: equal is 0 apart, anything else infinitely far (not 0 / 0 = NaN).
  if (den == 0.0) return num == 0.0 ? 0.0 : num > 0.0 ? std::numeric_limits<double>::infinity() : num;  // num NaN
  return std::sqrt(num / den);
}

}  // namespace lashid::sim::stats
