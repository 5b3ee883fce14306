// Firmware configurations of the paper's two examples (the host scenarios dis_paper and ais_paper).
#pragma once

#include <array>

#include "lashid/firmware/config.hpp"

namespace lashid::fw {

/// Section 3.5: backlash, [v_m, v_M] = [-3, 4], L = N = 2000. V_a is not in the paper (symmetric to V_d).
struct DisPaperConfig {
  static constexpr int kOrder = 2;
  static constexpr int kPoints = 6;
  static constexpr float kVMin = -3.0f;
  static constexpr float kVMax = 4.0f;
  static constexpr std::array<float, 6> kVd{-3.0f, -2.0f, -1.0f, 1.0f, 2.0f, 3.0f};
  static constexpr std::array<float, 6> kVa{4.0f, 3.0f, 2.0f, 1.0f, -1.0f, -2.0f};
  static constexpr int kStepLength = 2000;
  static constexpr int kPulseLengthD = 2000;
  static constexpr int kPulseLengthA = 2000;
  static constexpr bool kCheckInterval = true;  // backlash: the interval must be wide enough (Assumption 1)
  static constexpr float kCrossCheckSigmas = 4.0f;
};
static_assert(design_rules_hold<DisPaperConfig>());

/// Section 4.2: switch, [v_m, v_M] = [-2, 2], L = 2000, N = 8000. V_d is not in the paper (symmetric to V_a).
struct AisPaperConfig {
  static constexpr int kOrder = 2;
  static constexpr int kPoints = 6;
  static constexpr float kVMin = -2.0f;
  static constexpr float kVMax = 2.0f;
  static constexpr std::array<float, 6> kVd{-2.0f, -1.5f, -1.0f, 0.0f, 0.5f, 1.0f};
  static constexpr std::array<float, 6> kVa{2.0f, 1.5f, 1.0f, 0.0f, -0.5f, -1.0f};
  static constexpr int kStepLength = 2000;
  static constexpr int kPulseLengthD = 8000;
  static constexpr int kPulseLengthA = 8000;
  static constexpr bool kCheckInterval = false;  // a switch has no interval condition
  static constexpr float kCrossCheckSigmas = 4.0f;
};
static_assert(design_rules_hold<AisPaperConfig>());

}  // namespace lashid::fw
