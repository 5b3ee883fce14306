// The regime search of a backlash fit (see joint_model_regime_search.hpp).
#include "joint_model_regime_search.hpp"

#include <cstddef>
#include <utility>

#include "lashid/estimator/design.hpp"

namespace lashid::sim::detail {

namespace {

enum Label : signed char { kDown = -1, kHold = 0, kUp = 1 };

std::vector<signed char> labels_of(const Basis& phi, const std::vector<double>& w) {
  std::vector<signed char> label(w.size(), kHold);
  for (std::size_t t = 1; t < w.size(); ++t) {
    if (!(phi[t] == phi[t - 1])) label[t] = w[t] > w[t - 1] ? kUp : kDown;
  }
  return label;
}

Basis basis_of(const std::vector<signed char>& label, const Layout& layout, const std::vector<double>& w,
               const HatRow& first) {
  Basis phi(w.size());
  if (w.empty()) return phi;
  phi[0] = first;
  for (std::size_t t = 1; t < w.size(); ++t) {
    phi[t] = label[t] == kHold ? phi[t - 1] : hat_row(label[t] == kUp ? layout.ascending : layout.descending, w[t]);
  }
  return phi;
}

struct PulseRun {
  std::size_t begin, end;
};

// The DIS and AIS phases that last three periods or more.
std::vector<PulseRun> pulse_runs(const FlatRecording& data, std::size_t period) {
  std::vector<PulseRun> runs;
  for (std::size_t t = 0; t < data.size();) {
    std::size_t end = t;
    while (end < data.size() && data.phase[end] == data.phase[t]) ++end;
    const bool pulses = data.phase[t] == Phase::kDis || data.phase[t] == Phase::kAis;
    if (pulses && end - t >= 3 * period) runs.push_back({t, end});
    t = end;
  }
  return runs;
}

}  // namespace

RegimeSearch search_regimes(const ExperimentConfig& config, const Layout& layout, const FlatRecording& data,
                            const std::vector<double>& w, JointModel model, Basis phi, const FitForRegimes& fit) {
  RegimeSearch result{std::move(model), std::move(phi), 0};
  const auto period = static_cast<std::size_t>(est::schedule::period(config.n, config.m));
  const std::vector<PulseRun> runs = pulse_runs(data, period);
  if (!result.model.ok || runs.empty()) return result;
  std::vector<signed char> label = labels_of(result.phi, w);
  double own = self_consistent_rss(result.model, data);
  for (int round = 0; round < kRegimeSearchRounds; ++round) {
    JointModel best;
    std::vector<signed char> best_label;
    Basis best_phi;
    double best_own = own * (1.0 - kRegimeSearchGain);
    for (const PulseRun& run : runs) {
      // The pattern is read in a period from the middle of the phase, past its start's transient.
      const std::size_t reference = run.begin + (run.end - run.begin) / (2 * period) * period;
      for (std::size_t k = 0; k < period; ++k) {
        const std::size_t r = reference + k;
        if (w[r] == w[r - 1]) continue;  // the input stands still: the operator can only hold
        const signed char from = label[r];
        const signed char to = from != kHold ? kHold : (w[r] > w[r - 1] ? kUp : kDown);
        std::vector<signed char> changed = label;
        for (std::size_t t = run.begin + 2 * period + k; t < run.end; t += period) {
          // Only where the input repeats the reference period's (the samples before t and at t).
          const bool repeats = data.v[t] == data.v[reference + k] && data.v[t - 1] == data.v[reference + k - 1];
          if (repeats && changed[t] == from) changed[t] = to;
        }
        Basis candidate_phi = basis_of(changed, layout, w, result.phi[0]);
        JointModel candidate = fit(candidate_phi, result.model);
        if (!candidate.ok) continue;
        const double candidate_own = self_consistent_rss(candidate, data);
        if (candidate_own < best_own) {
          best_own = candidate_own;
          best = std::move(candidate);
          best_label = std::move(changed);
          best_phi = std::move(candidate_phi);
        }
      }
    }
    if (!best.ok) break;
    own = best_own;
    label = std::move(best_label);
    result.model = std::move(best);
    result.phi = std::move(best_phi);
    ++result.changes;
  }
  return result;
}

}  // namespace lashid::sim::detail
