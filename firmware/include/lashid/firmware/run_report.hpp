// Between a run's design and the estimator: each scheme's experiment design, and what a run reports (messages.hpp's
// records) made from the estimator's results: a scheme's estimate as its EstimateRecord, and the Remark 3b
// cross-check of the two linear estimates as reported. Free functions, so that the
// sequencer (sequencer.hpp) keeps to the order of the experiments. Header-only, heap-free, float32.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>

#include "lashid/estimator/cross_check.hpp"
#include "lashid/estimator/identifier.hpp"
#include "lashid/firmware/messages.hpp"
#include "lashid/firmware/run_design.hpp"

namespace lashid::fw {

/// Remark 3b threshold, in standard errors of the difference.
inline constexpr float kCrossCheckSigmas = 4.0f;

/// One scheme's experiment design (the estimator's view) of a run's design.
inline est::ExperimentDesign<float, kMaxPoints> scheme_design(const RunDesign& run, est::Scheme scheme) {
  est::ExperimentDesign<float, kMaxPoints> d;
  d.scheme = scheme;
  d.m = run.m;
  d.v_min = run.v_min;
  d.v_max = run.v_max;
  const auto& V = scheme == est::Scheme::kDescending ? run.V_d : run.V_a;
  for (int j = 0; j < run.m; ++j) d.V(j) = V[static_cast<std::size_t>(j)];
  return d;
}

/// The record of a scheme that did not run (reported as such when a run ends early).
constexpr EstimateRecord not_run(est::Scheme scheme) {
  EstimateRecord r;
  r.scheme = scheme;
  r.status = static_cast<std::uint8_t>(est::Status::kNotExcited);
  return r;
}

constexpr bool scheme_ok(const EstimateRecord& r) { return r.status == static_cast<std::uint8_t>(est::Status::kOk); }

/// A scheme's estimate for the run's design, with the standard errors of b from those of mu (cross_check.hpp).
template <int N, int M>
EstimateRecord to_record(const est::SchemeEstimate<float, N, M>& e, est::Scheme scheme, const RunDesign& design) {
  EstimateRecord r;
  r.scheme = scheme;
  r.status = static_cast<std::uint8_t>(e.status);
  r.n = design.n;
  r.m = design.m;
  r.ybar0 = e.ybar0;
  r.noise_variance = e.ls.noise_variance;
  if (e.status != est::Status::kOk) {
    // A failed estimate writes no a, b, F (estimate_into returns early): what `e` still holds is an earlier
    // period's, or the other scheme's, and must not be reported as this one's. NaN says "no value" on the host.
    constexpr float kNone = std::numeric_limits<float>::quiet_NaN();
    r.noise_variance = kNone;
    if (e.status == est::Status::kStepMeanMissing || e.status == est::Status::kNotConfigured) r.ybar0 = kNone;
    for (int i = 0; i < design.n; ++i) {
      const auto k = static_cast<std::size_t>(i);
      r.a[k] = r.se_a[k] = r.b[k] = r.se_b[k] = kNone;
    }
    for (int j = 0; j < design.m; ++j) r.F[static_cast<std::size_t>(j)] = kNone;
    return r;
  }
  for (int i = 0; i < design.n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    r.a[k] = e.a(i);
    r.se_a[k] = e.ls.std_error(i);
    r.b[k] = e.b(i);
    r.se_b[k] = est::b_std_error(e.ls.std_error(design.n + i), design.v_min, design.v_max);
  }
  for (int j = 0; j < design.m; ++j) r.F[static_cast<std::size_t>(j)] = e.F(j);
  return r;
}

/// Remark 3b on the reported a, b and standard errors; max_z = -1 (not available) unless both schemes succeeded.
inline CrossCheckRecord cross_check_of(const EstimateRecord& dis, const EstimateRecord& ais) {
  CrossCheckRecord out;
  out.threshold = kCrossCheckSigmas;
  if (!scheme_ok(dis) || !scheme_ok(ais)) {
    out.max_z = -1.0f;
    return out;
  }
  const auto linear = [](const EstimateRecord& r) {
    const auto n = static_cast<std::size_t>(r.n);
    return est::LinearEstimate<float>{std::span<const float>(r.a.data(), n), std::span<const float>(r.se_a.data(), n),
                                      std::span<const float>(r.b.data(), n), std::span<const float>(r.se_b.data(), n)};
  };
  const est::CrossCheck<float> c = est::cross_check(linear(dis), linear(ais));
  out.max_z = c.max_z;
  out.worst = static_cast<std::uint8_t>(c.worst);
  out.disagree = out.max_z > out.threshold ? 1 : 0;
  return out;
}

}  // namespace lashid::fw
