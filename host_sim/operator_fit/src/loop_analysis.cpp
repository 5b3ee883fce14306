// Error of a simulated operator by phase of the measured loop (declared in operator_fit.hpp).
#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include "lashid/operator_fit/operator_fit.hpp"
#include "lashid/stats/metrics.hpp"

namespace lashid::sim {

namespace {

// No reversal or no half-cycle of full travel: nothing measured, reported as 0.
double median_or_zero(const std::vector<double>& values) { return values.empty() ? 0.0 : stats::median(values); }

// Median |du/dv| over the first `window` of travel after each reversal.
double reversal_slope(std::span<const double> v, std::span<const double> u, const std::vector<std::size_t>& rev,
                      double window) {
  std::vector<double> slopes;
  for (std::size_t k = 0; k < rev.size(); ++k) {
    const std::size_t end = k + 1 < rev.size() ? rev[k + 1] : v.size();
    for (std::size_t t = rev[k] + 1; t < end; ++t) {
      const double travel = std::fabs(v[t] - v[rev[k]]);
      if (travel >= window) {
        slopes.push_back(std::fabs(u[t] - u[rev[k]]) / travel);
        break;
      }
    }
  }
  return median_or_zero(slopes);
}

// Median travel with |u| < threshold per half-cycle between reversals that travels at least `min_travel`; the
// spread (max - min) of the mean position of those samples over the half-cycles goes to *centre_spread.
double zero_force_gap(std::span<const double> v, std::span<const double> u, const std::vector<std::size_t>& rev,
                      double threshold, double min_travel, double* centre_spread = nullptr) {
  std::vector<double> gaps, centres;
  for (std::size_t k = 0; k + 1 < rev.size(); ++k) {
    if (std::fabs(v[rev[k + 1]] - v[rev[k]]) < min_travel) continue;
    double gap = 0, sum = 0, count = 0;
    for (std::size_t t = rev[k] + 1; t <= rev[k + 1]; ++t) {
      if (std::fabs(u[t]) < threshold) {
        gap += std::fabs(v[t] - v[t - 1]);
        sum += v[t];
        count += 1;
      }
    }
    gaps.push_back(gap);
    if (count > 0) centres.push_back(sum / count);
  }
  if (centre_spread != nullptr && !centres.empty()) {
    const auto [lowest, highest] = std::minmax_element(centres.begin(), centres.end());
    *centre_spread = *highest - *lowest;
  }
  return median_or_zero(gaps);
}

}  // namespace

LoopAnalysis analyse_loop(const DamperRecord& record, std::span<const double> u_sim, const LoopPhaseOptions& options) {
  const auto& v = record.v;
  const auto& u = record.u;
  if (u_sim.size() != u.size() || u.size() < 3) throw std::invalid_argument("analyse_loop: sizes differ or < 3");
  const std::vector<std::size_t> rev = reversal_indices(v, options.deadband);
  LoopAnalysis out;
  out.reversals = rev.size();

  // Speed over a centred window of about 50 ms, so that a flicker of the last bit of v is not motion.
  const double dt = (record.t.back() - record.t.front()) / static_cast<double>(record.t.size() - 1);
  // Clamped to the record before the cast: a time step that is tiny (or a span that is not finite) stays defined.
  const double half_window = std::round(0.025 / dt);
  const auto h = static_cast<std::size_t>(
      half_window >= 1 ? std::min(half_window, static_cast<double>(v.size())) : 1.0);  // NaN -> 1
  std::array<double, kLoopPhaseNames.size()> sse{};
  std::array<std::size_t, kLoopPhaseNames.size()> count{};
  std::vector<double> speeds;
  speeds.reserve(v.size());
  std::size_t last = 0;
  std::size_t next_rev = 0;
  for (std::size_t t = 0; t < v.size(); ++t) {
    while (next_rev < rev.size() && rev[next_rev] <= t) last = rev[next_rev++];
    const double travel = std::fabs(v[t] - v[last]);
    const std::size_t a = t >= h ? t - h : 0, b = std::min(v.size() - 1, t + h);
    const double speed = std::fabs(v[b] - v[a]) / (record.t[b] - record.t[a]);
    speeds.push_back(speed);
    LoopPhase phase = LoopPhase::kSliding;
    if (travel < options.reversal_window) {
      phase = LoopPhase::kReversal;
    } else if (speed < options.stick_speed) {
      phase = LoopPhase::kStick;
    } else if (travel < options.engagement_window) {
      phase = LoopPhase::kEngagement;
    }
    const double e = u[t] - u_sim[t];
    const auto p = static_cast<std::size_t>(phase);
    sse[p] += e * e;
    ++count[p];
  }
  double total = 0;
  for (double s : sse) total += s;
  for (std::size_t p = 0; p < kLoopPhaseNames.size(); ++p) {
    PhaseError pe;
    pe.phase = kLoopPhaseNames[p];
    pe.samples = count[p];
    pe.share_of_squared_error = total > 0 ? sse[p] / total : 0.0;
    pe.rms = count[p] > 0 ? std::sqrt(sse[p] / static_cast<double>(count[p])) : 0.0;
    out.phases.push_back(pe);
  }

  const auto q95 = speeds.begin() + static_cast<std::ptrdiff_t>(speeds.size() * 95 / 100);
  std::nth_element(speeds.begin(), q95, speeds.end());
  out.peak_speed = *q95;
  std::vector<double> magnitude(u.size());
  std::transform(u.begin(), u.end(), magnitude.begin(), [](double x) { return std::fabs(x); });
  const auto q90 = magnitude.begin() + static_cast<std::ptrdiff_t>(magnitude.size() * 9 / 10);
  std::nth_element(magnitude.begin(), q90, magnitude.end());
  out.plateau = *q90;
  out.measured_reversal_slope = reversal_slope(v, u, rev, options.reversal_window);
  out.simulated_reversal_slope = reversal_slope(v, u_sim, rev, options.reversal_window);
  out.measured_gap =
      zero_force_gap(v, u, rev, 0.1 * out.plateau, options.engagement_window, &out.measured_gap_centre_spread);
  out.simulated_gap = zero_force_gap(v, u_sim, rev, 0.1 * out.plateau, options.engagement_window);
  return out;
}

}  // namespace lashid::sim
