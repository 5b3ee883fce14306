// Cause rules of the friction damper: see damper_causes.hpp.
#include "lashid/operator_fit/damper_causes.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <utility>

#include <fmt/format.h>

namespace lashid::sim {

namespace {

// Sums over the test files of the nominal model's analyses; the rules divide by `files` for means.
struct NominalTotals {
  double files = 0;
  double reversal_share = 0;    // share of the squared error in the reversal phase
  double engagement_share = 0;  // same, engagement
  double measured_slope = 0;    // reversal slopes
  double simulated_slope = 0;
  double measured_gap = 0;  // zero-force travel per half-cycle
  double simulated_gap = 0;
  double plateau = 0;       // friction level
  double gap_spread = 0;    // not a sum: the largest spread of the gap's position over the files
};

NominalTotals totals(const std::vector<LoopAnalysis>& nominal) {
  NominalTotals t;
  for (const auto& a : nominal) {
    t.gap_spread = std::max(t.gap_spread, a.measured_gap_centre_spread);
    t.reversal_share += a.phase(LoopPhase::kReversal).share_of_squared_error;
    t.engagement_share += a.phase(LoopPhase::kEngagement).share_of_squared_error;
    t.measured_slope += a.measured_reversal_slope;
    t.simulated_slope += a.simulated_reversal_slope;
    t.measured_gap += a.measured_gap;
    t.simulated_gap += a.simulated_gap;
    t.plateau += a.plateau;
  }
  t.files = static_cast<double>(nominal.size());
  return t;
}

std::optional<DamperCause> finite_stiffness_at_reversal(const NominalTotals& t, const DamperCauseOptions& o) {
  const double n = t.files;
  if (!((t.reversal_share + t.engagement_share) / n > o.reversal_error_share)) return std::nullopt;
  return DamperCause{"finite_stiffness_at_reversal", true,
                     fmt::format("on average {:.0f} % (reversal) + {:.0f} % (engagement) of the nominal squared error "
                                 "follows a reversal; measured force changes at {:.1f} per unit of v just after "
                                 "reversals, the nominal simulation at {:.1f}",
                                 100 * t.reversal_share / n, 100 * t.engagement_share / n, t.measured_slope / n,
                                 t.simulated_slope / n)};
}

std::optional<DamperCause> zero_force_gap_moving_with_reversal(const NominalTotals& t, const DamperCauseOptions& o) {
  const double n = t.files;
  // A gap that stays in one place could be a border's zero crossing; one that moves further than its own width
  // follows the reversal point.
  if (!(t.measured_gap / n > o.min_gap && t.gap_spread > t.measured_gap / n)) return std::nullopt;
  return DamperCause{"zero_force_gap_moving_with_reversal", true,
                     fmt::format("the measured force stays below 10 % of the friction level for {:.3f} of travel per "
                                 "half-cycle (nominal simulation: {:.3f}), and the position of this gap spreads over "
                                 "{:.3f} across half-cycles: it follows the last reversal, which no border C(v) of v "
                                 "alone can represent",
                                 t.measured_gap / n, t.simulated_gap / n, t.gap_spread)};
}

std::optional<DamperCause> position_dependent_friction(const NominalTotals& t, const ExtendedFit& fit, double v_span,
                                                       const DamperCauseOptions& o) {
  const double n = t.files;
  if (!(std::fabs(fit.stiffness) * v_span > o.stiffness_force_share * t.plateau / n)) return std::nullopt;
  return DamperCause{"position_dependent_friction", true,
                     fmt::format("the sliding force changes with displacement at {:.3f} per unit of v (fitted "
                                 "parallel stiffness), {:.0f} % of the friction level over the training range",
                                 fit.stiffness, 100 * std::fabs(fit.stiffness) * v_span / (t.plateau / n))};
}

// The extended (rate-independent) model's sliding error at the fastest against the slowest test file.
std::optional<DamperCause> rate_dependence(const std::vector<LoopAnalysis>& extended, const DamperCauseOptions& o) {
  std::vector<const LoopAnalysis*> sliding;
  for (const auto& a : extended) {
    if (a.phase(LoopPhase::kSliding).samples > 0) sliding.push_back(&a);
  }
  if (sliding.size() < 2) return std::nullopt;
  std::stable_sort(sliding.begin(), sliding.end(),
                   [](const LoopAnalysis* a, const LoopAnalysis* b) { return a->peak_speed < b->peak_speed; });
  const LoopAnalysis& slowest = *sliding.front();
  const LoopAnalysis& fastest = *sliding.back();
  const double slow_rms = slowest.phase(LoopPhase::kSliding).rms;
  const double fast_rms = fastest.phase(LoopPhase::kSliding).rms;
  if (!(fast_rms > o.sliding_rms_ratio * slow_rms)) return std::nullopt;
  return DamperCause{"rate_dependence", false,
                     fmt::format("the extended model's RMS error while sliding is {:.3f} at a peak speed of {:.2f} "
                                 "per s and {:.3f} at {:.2f} per s (force oscillation on the plateau); the operators "
                                 "are rate-independent",
                                 fast_rms, fastest.peak_speed, slow_rms, slowest.peak_speed)};
}

}  // namespace

std::vector<DamperCause> damper_causes(const std::vector<LoopAnalysis>& nominal,
                                       const std::vector<LoopAnalysis>& extended, const ExtendedFit& extended_fit,
                                       double v_span, const DamperCauseOptions& options) {
  std::vector<DamperCause> out;
  if (nominal.empty()) return out;
  const NominalTotals t = totals(nominal);
  const auto add = [&out](std::optional<DamperCause> cause) {
    if (cause) out.push_back(std::move(*cause));
  };
  add(finite_stiffness_at_reversal(t, options));
  add(zero_force_gap_moving_with_reversal(t, options));
  add(position_dependent_friction(t, extended_fit, v_span, options));
  add(rate_dependence(extended, options));
  return out;
}

std::string output_dynamics_in_words(const std::vector<FilterPole>& poles, int order, const TestErrors& errors) {
  FilterPole dominant;
  if (!dominant_pole(poles, &dominant)) return "no dynamics after the friction element (a filter without poles)";
  const double removed = errors.extended > 0 ? 1.0 - errors.with_dynamics / errors.extended : 0.0;
  const std::string gain = fmt::format(
      "(dominant pole of the order-{} B(q)/A(q) after the friction_gap operator, identified on the training files "
      "only); with it the extended model's squared error on the test files {} by {:.1f} % (mean test fit {:.1f} "
      "% -> {:.1f} %)",
      order, removed >= 0 ? "drops" : "grows", 100 * std::fabs(removed), errors.mean_fit_extended,
      errors.mean_fit_dynamics);
  if (dominant.z.imag() > 0) {
    return fmt::format("the measured force rings at {:.1f} Hz after reversals: dynamics after the friction element, "
                       "damping zeta = {:.2f}, natural frequency {:.1f} Hz {}",
                       dominant.damped_hz, dominant.zeta, dominant.natural_hz, gain);
  }
  // A real pole: the force follows the friction element with a lag, it does not ring.
  const double time_constant_ms = dominant.natural_hz > 0 ? 1000.0 / (2 * std::numbers::pi * dominant.natural_hz) : 0;
  return fmt::format("the measured force lags the friction element without ringing: a real pole at {:.1f} Hz (time "
                     "constant {:.1f} ms) {}",
                     dominant.natural_hz, time_constant_ms, gain);
}

std::optional<DamperCause> dynamics_after_friction_element(const std::vector<FilterPole>& poles, int order,
                                                           const TestErrors& errors,
                                                           const DamperCauseOptions& options) {
  if (poles.empty() || !(errors.extended > 0)) return std::nullopt;
  if (!(1.0 - errors.with_dynamics / errors.extended >= options.dynamics_error_reduction)) return std::nullopt;
  return DamperCause{"dynamics_after_friction_element", true, output_dynamics_in_words(poles, order, errors)};
}

}  // namespace lashid::sim
