// The runs of the paper's two examples (the host scenarios dis_paper and ais_paper) as run-time designs: est::paper's
// numbers, plus what only a run decides, the operator (which sets the interval check) and no validation phase.
#pragma once

#include <cstddef>

#include "lashid/estimator/paper_designs.hpp"
#include "lashid/firmware/run_design.hpp"

namespace lashid::fw {

template <class PaperDesign>
constexpr RunDesign paper_run_design(const PaperDesign& p, OperatorKind op) {
  RunDesign d;
  d.op = op;
  d.n = static_cast<std::uint8_t>(p.n);
  d.m = static_cast<std::uint8_t>(p.m);
  d.v_min = p.v_min;
  d.v_max = p.v_max;
  for (std::size_t j = 0; j < p.V_d.size(); ++j) {
    d.V_d[j] = p.V_d[j];
    d.V_a[j] = p.V_a[j];
  }
  d.step_length = static_cast<std::uint32_t>(p.step_length);
  d.pulse_length_d = static_cast<std::uint32_t>(p.pulse_length_d);
  d.pulse_length_a = static_cast<std::uint32_t>(p.pulse_length_a);
  return d;
}

/// Section 3.5: backlash (interval check), [v_m, v_M] = [-3, 4], L = N = 2000.
inline constexpr RunDesign kDisPaperRun = paper_run_design(est::paper::kDisPaper<float>, OperatorKind::kBacklash);
/// Section 4.2: switch, [v_m, v_M] = [-2, 2], L = 2000, N = 8000.
inline constexpr RunDesign kAisPaperRun = paper_run_design(est::paper::kAisPaper<float>, OperatorKind::kSwitch);

static_assert(check_design(kDisPaperRun) == DesignStatus::kOk);
static_assert(check_design(kAisPaperRun) == DesignStatus::kOk);

}  // namespace lashid::fw
