// Status codes of the estimator. Numerical or input failure is a returned status, never an exception or a crash.
#pragma once

#include <cmath>
#include <cstdint>

namespace lashid::est {

enum class [[nodiscard]] Status : std::uint8_t {
  kOk = 0,
  kNotConfigured,        ///< the identifier has no valid design yet
  kOrderOutOfRange,      ///< n or m outside the range the caller supports
  kIntervalInvalid,      ///< v_min >= v_max, or a bound is not finite
  kAbscissasNotOrdered,  ///< V_j violate v_m = V_1^d < ... < V_m^d < v_M (DIS) or v_M = V_1^a > ... > V_m^a > v_m (AIS)
  kNonFinite,            ///< a sample (v or y) is NaN or infinite, or y too large for the sums (usable())
  kInputOffDesign,       ///< v(t) is not the held level or a design abscissa, or two pulses fall within n samples
  kStepMeanMissing,      ///< a pulse sample arrived before the step experiment produced a mean
  kNotExcited,           ///< some parameter has not been excited yet (too few samples)
  kIllConditioned,       ///< the (reduced) normal matrix is too ill-conditioned for the scalar type
  kDegenerateGain,       ///< sum b_i^2 = 0 or B(1) = 0: (3.22b)/(3.23) cannot be evaluated
  // After the others, so that their codes keep their values in the firmware's reports.
  kAbscissasTooClose,    ///< ordered, but two V_j (or one and the held level) closer than classify() resolves
};

constexpr const char* to_string(Status s) {
  switch (s) {
    case Status::kOk: return "ok";
    case Status::kNotConfigured: return "not configured";
    case Status::kOrderOutOfRange: return "order out of range";
    case Status::kIntervalInvalid: return "working interval invalid (need finite v_min < v_max)";
    case Status::kAbscissasNotOrdered: return "abscissas not ordered as the paper requires";
    case Status::kNonFinite: return "non-finite or too large sample";
    case Status::kInputOffDesign: return "input not on the experiment design";
    case Status::kStepMeanMissing: return "pulse sample before the step-experiment mean";
    case Status::kNotExcited: return "not excited yet";
    case Status::kIllConditioned: return "ill-conditioned normal matrix";
    case Status::kDegenerateGain: return "degenerate gain (sum b_i^2 = 0 or B(1) = 0)";
    case Status::kAbscissasTooClose: return "abscissas closer than the classifier resolves (2 x 64 eps of the largest)";
  }
  return "unknown status";
}

constexpr bool ok(Status s) { return s == Status::kOk; }

/// x is neither NaN nor infinite: x - x is 0 exactly for finite x and NaN otherwise. Two instructions and a branch
/// on Cortex-M4F, against a classification for std::isfinite; the per-sample checks use it.
template <class Scalar>
constexpr bool finite(Scalar x) {
  return x - x == Scalar(0);
}

/// The largest |y| the estimator takes: the sums of squares and products of 2^32 such samples stay finite
/// (sqrt(max / 2^32): 2.8e14 in float32, 2e149 in double). One larger but finite sample overflowed the float32
/// sums and left every later estimate ill-conditioned; it is now refused like a NaN.
template <class Scalar>
inline constexpr Scalar kMaxSampleMagnitude = Scalar(1e14);
template <>
inline constexpr double kMaxSampleMagnitude<double> = 1e140;

/// Finite and within kMaxSampleMagnitude (false for NaN: every comparison with it is). One fabs and one compare: it
/// is on the path of every sample.
template <class Scalar>
inline bool usable(Scalar x) {
  return std::fabs(x) < kMaxSampleMagnitude<Scalar>;
}

}  // namespace lashid::est
