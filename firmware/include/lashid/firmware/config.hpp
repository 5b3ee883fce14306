// Compile-time configuration of the identification firmware: model orders, working interval, abscissas, lengths.
// The design rules of the paper are checked by static_assert where a configuration is used, so a firmware image
// with an invalid design does not build.
#pragma once

#include <array>
#include <concepts>
#include <cstddef>

#include "lashid/estimator/design.hpp"

namespace lashid::fw {

template <class C>
concept FirmwareConfig = requires {
  { C::kOrder } -> std::convertible_to<int>;         // n
  { C::kPoints } -> std::convertible_to<int>;        // m
  { C::kVMin } -> std::convertible_to<float>;        // v_m
  { C::kVMax } -> std::convertible_to<float>;        // v_M
  { C::kVd[0] } -> std::convertible_to<float>;       // V_1^d .. V_m^d
  { C::kVa[0] } -> std::convertible_to<float>;       // V_1^a .. V_m^a
  { C::kStepLength } -> std::convertible_to<int>;    // L: the step phases have L + 1 samples
  { C::kPulseLengthD } -> std::convertible_to<int>;  // N of the DP experiment
  { C::kPulseLengthA } -> std::convertible_to<int>;  // N of the AP experiment
  { C::kCheckInterval } -> std::convertible_to<bool>;  // Section 3.4 step 1 (backlash)
  { C::kCrossCheckSigmas } -> std::convertible_to<float>;  // Remark 3b threshold, in standard errors
};

/// The paper's design rules: (3.1) v_m = V_1^d < ... < V_m^d < v_M, (4.2) v_M = V_1^a > ... > V_m^a > v_m,
/// L > n, and at least two pulse periods (Theorem 3.1) per pulse experiment.
template <FirmwareConfig C>
constexpr bool design_rules_hold() {
  constexpr int n = C::kOrder;
  constexpr int m = C::kPoints;
  if (n < 1 || m < 1 || static_cast<int>(C::kVd.size()) != m || static_cast<int>(C::kVa.size()) != m) return false;
  if (!(C::kVMin < C::kVMax)) return false;
  if (C::kVd[0] != C::kVMin || !(C::kVd[m - 1] < C::kVMax)) return false;
  if (C::kVa[0] != C::kVMax || !(C::kVa[m - 1] > C::kVMin)) return false;
  for (std::size_t j = 1; j < static_cast<std::size_t>(m); ++j) {
    if (!(C::kVd[j - 1] < C::kVd[j]) || !(C::kVa[j - 1] > C::kVa[j])) return false;
  }
  const int period = est::schedule::period(n, m);
  return C::kStepLength > n && C::kPulseLengthD >= 2 * period && C::kPulseLengthA >= 2 * period;
}

}  // namespace lashid::fw
