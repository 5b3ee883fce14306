#include "lashid/operator_fit/test_profiles.hpp"

#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "lashid/operator_fit/operator_fit.hpp"

namespace lashid::sim {

namespace {

void check_record(const DamperRecord& record, const char* what) {
  if (record.u.size() < 2 || record.v.size() != record.u.size()) {
    throw std::invalid_argument(fmt::format("{}: {}: needs a record of at least 2 samples", what, record.source));
  }
}

void add_point(FitProfile& profile, double value, double fit) {
  profile.points.emplace_back(value, fit);
  if (profile.points.size() == 1 || fit > profile.best_fit) {
    profile.best_value = value;
    profile.best_fit = fit;
  }
}

}  // namespace

FitProfile initial_offset_profile(const FrictionGapOperator& op, const OutputFilter& dynamics,
                                  const DamperRecord& record, int points) {
  if (points < 2) throw std::invalid_argument(fmt::format("initial_offset_profile: points = {} < 2", points));
  check_record(record, "initial_offset_profile");
  FitProfile profile{"initial_offset_in", {}, 0, -std::numeric_limits<double>::infinity()};
  const double lo = op.curve().lo(), hi = op.curve().hi();
  std::vector<double> u(record.v.size());
  for (int k = 0; k < points; ++k) {
    const double e0 = k + 1 == points ? hi : lo + (hi - lo) * k / (points - 1.0);
    FrictionGapOperator copy = op;
    copy.place(record.v.front(), e0);
    u.front() = record.u.front();
    for (std::size_t t = 1; t < u.size(); ++t) u[t] = copy.step(record.v[t]);
    add_point(profile, e0, fit_to_record(record, dynamics.apply(u, record.u.front())));
  }
  return profile;
}

FitProfile tension_profile(const TensionFrictionFit& fit, const OutputFilter& dynamics, const DamperRecord& record,
                           double lo, double hi, double step) {
  if (!std::isfinite(lo) || !std::isfinite(hi) || !std::isfinite(step) || !(lo >= 0) || !(lo <= hi) ||
      !(step > 0)) {
    throw std::invalid_argument(
        fmt::format("tension_profile: needs finite 0 <= lo <= hi and step > 0, got lo {}, hi {}, step {}", lo, hi,
                    step));
  }
  check_record(record, "tension_profile");
  FitProfile profile{"tension_lb", {}, 0, -std::numeric_limits<double>::infinity()};
  for (int k = 0;; ++k) {
    const double tension = lo + step * k;
    if (tension > hi + 1e-9) break;
    std::unique_ptr<FrictionGapOperator> op;
    try {
      op = fit.make(tension);
    } catch (const std::invalid_argument&) {
      continue;  // no valid operator at this tension (extrapolated too far): not a point of the profile
    }
    const std::vector<double> u = simulate_operator(*op, record.v, record.u.front());
    add_point(profile, tension, fit_to_record(record, dynamics.apply(u, record.u.front())));
  }
  return profile;
}

}  // namespace lashid::sim
