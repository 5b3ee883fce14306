// Firmware configurations of the paper's two examples (the host scenarios dis_paper and ais_paper). The designs
// (n, m, interval, abscissas, lengths) are est::paper's, the same numbers the simulator's scenarios use; the
// firmware adds what only it decides: the interval check and the cross-check threshold.
#pragma once

#include <array>

#include "lashid/estimator/paper_designs.hpp"
#include "lashid/firmware/config.hpp"

namespace lashid::fw {

/// The FirmwareConfig members a paper design determines, in float32 as the firmware computes.
template <const auto& D>
struct PaperDesignConfig {
  static constexpr int kOrder = D.n;
  static constexpr int kPoints = D.m;
  static constexpr float kVMin = D.v_min;
  static constexpr float kVMax = D.v_max;
  static constexpr auto kVd = D.V_d;  // std::array<float, m>
  static constexpr auto kVa = D.V_a;
  static constexpr int kStepLength = D.step_length;
  static constexpr int kPulseLengthD = D.pulse_length_d;
  static constexpr int kPulseLengthA = D.pulse_length_a;
};

/// Section 3.5: backlash, [v_m, v_M] = [-3, 4], L = N = 2000.
struct DisPaperConfig : PaperDesignConfig<est::paper::kDisPaper<float>> {
  static constexpr bool kCheckInterval = true;  // backlash: the interval must be wide enough (Assumption 1)
  static constexpr float kCrossCheckSigmas = 4.0f;
};
static_assert(design_rules_hold<DisPaperConfig>());

/// Section 4.2: switch, [v_m, v_M] = [-2, 2], L = 2000, N = 8000.
struct AisPaperConfig : PaperDesignConfig<est::paper::kAisPaper<float>> {
  static constexpr bool kCheckInterval = false;  // a switch has no interval condition
  static constexpr float kCrossCheckSigmas = 4.0f;
};
static_assert(design_rules_hold<AisPaperConfig>());

}  // namespace lashid::fw
