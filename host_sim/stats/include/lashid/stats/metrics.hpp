// Summary measures of data and of a model's fit to it: the system-identification fit percentage, the median, and
// the relative difference of two parameter vectors.
// Bad arguments throw std::invalid_argument with a message naming the function and the offending value.
#pragma once

#include <span>

namespace lashid::sim::stats {

// System-identification fit percentage (Ljung 1999, MATLAB "compare"):
//   fit = 100 (1 - ||y - yhat|| / ||y - mean(y)||),
// 100 for a perfect simulation, 0 for the constant mean, negative for worse than the mean. Requires equal
// lengths N >= 2, finite samples and a non-constant measured y. A caller that must score a diverged simulation
// (non-finite samples) decides itself what that scores, e.g. -inf.
double fit_percent(std::span<const double> measured, std::span<const double> simulated);

// Median of x: the middle value for an odd size, the mean of the two middle values for an even size. Requires a
// non-empty x of finite samples. x is copied (the selection reorders the copy), so the caller's order is kept.
double median(std::span<const double> x);

// ||x - ref|| / ||ref|| (Euclidean norms): how far an estimate is from a reference (the truth, the paper's numbers,
// another build of the same estimator). x and ref must have the same length (std::invalid_argument otherwise); a
// zero ref gives 0 for a zero x and infinity for any other; a NaN anywhere gives NaN.
double relative_difference(std::span<const double> x, std::span<const double> ref);

}  // namespace lashid::sim::stats
