#include "lashid/hil/verdict.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "lashid/stats/metrics.hpp"

namespace lashid::sim {
namespace {

std::vector<double> flatten(const fw::EstimateRecord& e) {
  std::vector<double> x;
  for (int i = 0; i < e.n; ++i) x.push_back(static_cast<double>(e.a[static_cast<std::size_t>(i)]));
  for (int i = 0; i < e.n; ++i) x.push_back(static_cast<double>(e.b[static_cast<std::size_t>(i)]));
  for (int j = 0; j < e.m; ++j) x.push_back(static_cast<double>(e.F[static_cast<std::size_t>(j)]));
  return x;
}

// The first estimate of `scheme` in `estimates`, if any.
const fw::EstimateRecord* find_estimate(const std::vector<fw::EstimateRecord>& estimates, est::Scheme scheme) {
  const auto it = std::find_if(estimates.begin(), estimates.end(),
                               [&](const fw::EstimateRecord& e) { return e.scheme == scheme; });
  return it == estimates.end() ? nullptr : &*it;
}

// The run's usable estimates (by scheme, as in `v`) against `reference`, scheme by scheme: the largest
// ||x - x_ref|| / ||x_ref||, and whether both sides have the same schemes.
struct EstimateDifference {
  double max_relative = 0;
  bool same_schemes = true;
};

EstimateDifference difference(const HilResult& run, const HilVerdict& v,
                              const std::vector<fw::EstimateRecord>& reference) {
  EstimateDifference out;
  for (const est::Scheme scheme : {est::Scheme::kDescending, est::Scheme::kAscending}) {
    const std::optional<std::size_t>& k = scheme == est::Scheme::kDescending ? v.dis : v.ais;
    const fw::EstimateRecord* r = find_estimate(reference, scheme);
    if (!k.has_value() || r == nullptr) {
      out.same_schemes = out.same_schemes && !k.has_value() && r == nullptr;
      continue;
    }
    const std::vector<double> x = flatten(run.estimates[*k]), ref = flatten(*r);
    // Different shapes (n, m) or a NaN are as different as can be, not silently skipped.
    const double d = x.size() == ref.size() ? stats::relative_difference(x, ref)
                                             : std::numeric_limits<double>::infinity();
    out.max_relative = std::isnan(d) ? std::numeric_limits<double>::infinity() : std::max(out.max_relative, d);
  }
  return out;
}

HostComparison compare(const HilResult& run, const HilVerdict& v, const HilResult& host, double tolerance) {
  HostComparison c;
  c.samples = run.samples;
  c.host_samples = host.samples;
  const EstimateDifference d = difference(run, v, host.estimates);
  c.max_relative_difference = d.max_relative;
  c.equal = d.same_schemes && c.samples == c.host_samples && c.max_relative_difference <= tolerance;
  return c;
}

}  // namespace

RecordingComparison compare_with_recording(const HilResult& run, const HilVerdict& v,
                                           const std::vector<fw::EstimateRecord>& from_recording, double tolerance) {
  RecordingComparison c;
  const EstimateDifference d = difference(run, v, from_recording);
  c.max_relative_difference = d.max_relative;
  c.equal = d.same_schemes && c.max_relative_difference <= tolerance;
  return c;
}

bool HilVerdict::has(HilFailure f) const { return std::find(failures.begin(), failures.end(), f) != failures.end(); }

HilVerdict judge(const HilResult& run, const HilResult* host, const JudgeOptions& options) {
  HilVerdict v;
  const auto fail = [&v](HilFailure f) {
    if (!v.has(f)) v.failures.push_back(f);
  };
  if (run.done < 0) {
    fail(HilFailure::kNoDoneReport);
  } else if (run.done != static_cast<int>(fw::RunStatus::kOk)) {
    fail(HilFailure::kRunFailed);
  }
  if (!(run.qemu_exit == 0 || (options.attached && run.qemu_exit == -1))) fail(HilFailure::kQemuExit);

  bool dis_arrived = false, ais_arrived = false;
  for (std::size_t k = 0; k < run.estimates.size(); ++k) {
    const fw::EstimateRecord& e = run.estimates[k];
    const bool dis = e.scheme == est::Scheme::kDescending;
    (dis ? dis_arrived : ais_arrived) = true;
    if (e.n == 0 || e.m == 0) {
      fail(HilFailure::kEstimateEmpty);
      continue;
    }
    std::optional<std::size_t>& slot = dis ? v.dis : v.ais;
    if (!slot) slot = k;
  }
  if (!dis_arrived || !ais_arrived) fail(HilFailure::kEstimateMissing);

  // The firmware's own count of the samples it measured against what the host saw of them (its cost report; none
  // when the run ended before reporting, and then there is nothing to compare).
  if (run.cost) {
    if (options.plant_played && run.cost->samples != run.samples) fail(HilFailure::kPlantNotPlayed);
    if (options.streamed && run.samples < run.cost->samples) fail(HilFailure::kRecordingIncomplete);
  }
  if (host == nullptr && options.compare_host) fail(HilFailure::kDifferentFromHost);  // asked for, not made
  if (host != nullptr) {
    v.host = compare(run, v, *host, options.tolerance);
    if (!v.host->equal) fail(HilFailure::kDifferentFromHost);
  }
  if (run.corrupted_by_host > 0) {
    FaultInjection f;
    f.damaged = run.corrupted_by_host;
    f.re_requested = run.cost ? run.cost->retries : 0;
    f.all_detected = run.cost && f.re_requested >= f.damaged && run.cost->link_errors >= f.damaged;
    v.fault_injection = f;
    if (!f.all_detected) fail(HilFailure::kDamagedFramesMissed);
  }
  return v;
}

std::string cross_check_parameter(std::uint8_t worst, int n) {
  if (n <= 0) return fmt::format("parameter {}", worst);
  return worst < n ? fmt::format("a{}", worst + 1) : fmt::format("b{}", worst - n + 1);
}

}  // namespace lashid::sim
