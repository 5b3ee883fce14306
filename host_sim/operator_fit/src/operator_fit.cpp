// Direction and reversals, median borders, the nominal and the extended fits, simulation and fit of a record.
#include "lashid/operator_fit/operator_fit.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "lashid/stats/metrics.hpp"

namespace lashid::sim {

namespace {

// Nearest node of an equally spaced grid of `points` nodes over [lo, hi] (a finite span, see median_table). Defined
// for every v: below the grid, and NaN, give node 0, above it the last node, so the cast never sees inf or NaN.
std::size_t nearest_node(double v, double lo, double hi, int points) {
  const double position = (v - lo) / (hi - lo) * (points - 1);
  if (!(position > 0)) return 0;
  return static_cast<std::size_t>(std::min(std::round(position), static_cast<double>(points - 1)));
}

std::vector<std::pair<double, double>> median_table(std::span<const std::pair<double, double>> samples, double lo,
                                                    double hi, int points) {
  if (points < 2 || !(lo < hi) || !std::isfinite(hi - lo)) {
    throw std::invalid_argument(fmt::format("fit_border: need points >= 2 and lo < hi with a finite span hi - lo, "
                                            "got {}, [{}, {}]",
                                            points, lo, hi));
  }
  std::vector<std::vector<double>> bins(static_cast<std::size_t>(points));
  for (const auto& [v, u] : samples) bins[nearest_node(v, lo, hi, points)].push_back(u);
  std::vector<std::pair<double, double>> table;
  for (std::size_t i = 0; i < bins.size(); ++i) {
    if (bins[i].empty()) continue;
    table.emplace_back(lo + (hi - lo) * static_cast<double>(i) / (points - 1), stats::median(bins[i]));
  }
  if (table.size() < 2) throw std::invalid_argument("fit_border: fewer than 2 nodes have samples");
  return table;
}

void require_training(const std::vector<DamperRecord>& train) {
  if (train.empty()) throw std::invalid_argument("no training records");
  for (const auto& r : train) {
    if (r.v.size() < 2) throw std::invalid_argument(fmt::format("{}: fewer than 2 samples", r.source));
    check_damper_values(r);  // bounded v and u: every span, bin index and sum of squares below stays finite
  }
}

double mean_fit(const HysteresisOperator& op, const std::vector<DamperRecord>& train) {
  double sum = 0;
  for (const auto& r : train) sum += fit_to_record(r, simulate_operator(op, r.v, r.u.front()));
  return sum / static_cast<double>(train.size());
}

// Relative displacement e(t) = v(t) - z(t) of a play [-r, r] started mid-play (z = v(0)).
std::vector<double> play_offsets(std::span<const double> v, double r) {
  std::vector<double> e(v.size());
  double z = v.front();
  for (std::size_t t = 0; t < v.size(); ++t) {
    z = std::clamp(z, v[t] - r, v[t] + r);
    e[t] = v[t] - z;
  }
  return e;
}

}  // namespace

std::vector<int> motion_direction(std::span<const double> v, double deadband) {
  std::vector<int> direction(v.size(), 0);
  int current = 0;
  double high = v.empty() ? 0.0 : v.front(), low = high;
  std::size_t first_decided = v.size();
  for (std::size_t t = 0; t < v.size(); ++t) {
    high = std::max(high, v[t]);
    low = std::min(low, v[t]);
    if (current >= 0 && v[t] < high - deadband) {  // falling now
      current = -1;
      low = v[t];
    } else if (current <= 0 && v[t] > low + deadband) {
      current = +1;
      high = v[t];
    }
    if (current != 0 && first_decided == v.size()) first_decided = t;
    direction[t] = current;
  }
  const int first = first_decided < v.size() ? direction[first_decided] : 1;
  for (std::size_t t = 0; t < std::min(first_decided, v.size()); ++t) direction[t] = first;
  return direction;
}

std::vector<std::size_t> reversal_indices(std::span<const double> v, double deadband) {
  const std::vector<int> d = motion_direction(v, deadband);
  std::vector<std::size_t> out;
  std::size_t extreme = 0;
  for (std::size_t t = 1; t < v.size(); ++t) {
    if (d[t] != d[t - 1]) out.push_back(extreme);
    // The extreme of the current motion: the last max while rising, the last min while falling.
    if (d[t] != d[t - 1] || (d[t] > 0 ? v[t] >= v[extreme] : v[t] <= v[extreme])) extreme = t;
  }
  return out;
}

Border fit_border(std::span<const std::pair<double, double>> samples, double lo, double hi, int points) {
  return Border::from_table(median_table(samples, lo, hi, points));
}

std::vector<double> simulate_operator(const HysteresisOperator& op, std::span<const double> v, double u0) {
  std::vector<double> u(v.size());
  if (v.empty()) return u;
  auto copy = op.clone();
  copy->reset(v[0], u0);
  u[0] = u0;
  for (std::size_t t = 1; t < v.size(); ++t) u[t] = copy->step(v[t]);
  return u;
}

double fit_to_record(const DamperRecord& record, std::span<const double> u_sim) {
  if (!std::all_of(u_sim.begin(), u_sim.end(), [](double x) { return std::isfinite(x); })) {
    return -std::numeric_limits<double>::infinity();
  }
  try {
    return stats::fit_percent(record.u, u_sim);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(fmt::format("{}: cannot score a simulation: {}", record.source, e.what()));
  }
}

std::unique_ptr<HysteresisOperator> NominalFit::make() const {
  if (chosen == "switch") return std::make_unique<SwitchOperator>(ascending, descending);
  return std::make_unique<BacklashOperator>(ascending, descending);
}

NominalFit fit_nominal(const std::vector<DamperRecord>& train, const OperatorFitOptions& options) {
  require_training(train);
  std::vector<std::pair<double, double>> rising, falling;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const auto& r : train) {
    const std::vector<int> d = motion_direction(r.v, options.deadband);
    for (std::size_t t = 0; t < r.v.size(); ++t) (d[t] > 0 ? rising : falling).emplace_back(r.v[t], r.u[t]);
    lo = std::min(lo, *std::min_element(r.v.begin(), r.v.end()));
    hi = std::max(hi, *std::max_element(r.v.begin(), r.v.end()));
  }
  NominalFit fit{fit_border(rising, lo, hi, options.points), fit_border(falling, lo, hi, options.points), 0, 0, ""};
  fit.fit_train_switch = mean_fit(SwitchOperator(fit.ascending, fit.descending), train);
  fit.fit_train_backlash = mean_fit(BacklashOperator(fit.ascending, fit.descending), train);
  fit.chosen = fit.fit_train_switch >= fit.fit_train_backlash ? "switch" : "backlash";
  return fit;
}

std::unique_ptr<FrictionGapOperator> ExtendedFit::make() const {
  return std::make_unique<FrictionGapOperator>(Border::from_table(curve), stiffness);
}

CurveAtWidth fit_curve_at_width(const std::vector<DamperRecord>& records, double width,
                                const OperatorFitOptions& options) {
  require_training(records);
  if (!(width > 0)) throw std::invalid_argument(fmt::format("play half-width must be > 0, got {}", width));
  std::vector<std::vector<double>> offsets;
  std::size_t total = 0;
  for (const auto& r : records) {
    offsets.push_back(play_offsets(r.v, width));
    total += r.v.size();
  }
  CurveAtWidth out;
  std::vector<std::pair<double, double>> samples;
  samples.reserve(total);
  double k = 0;
  for (int round = 0; round < 3; ++round) {
    out.stiffness = k;  // the k that `out.curve` and `out.squared_error` are computed with
    samples.clear();
    for (std::size_t f = 0; f < records.size(); ++f) {
      for (std::size_t t = 0; t < records[f].v.size(); ++t) {
        samples.emplace_back(offsets[f][t], records[f].u[t] - k * records[f].v[t]);
      }
    }
    out.curve = median_table(samples, -width, width, options.points);
    const Border curve = Border::from_table(out.curve);
    double num = 0, den = 0;
    out.squared_error = 0;
    for (std::size_t f = 0; f < records.size(); ++f) {
      for (std::size_t t = 0; t < records[f].v.size(); ++t) {
        const double rest = records[f].u[t] - curve(offsets[f][t]);
        num += rest * records[f].v[t];
        den += records[f].v[t] * records[f].v[t];
        out.squared_error += (rest - k * records[f].v[t]) * (rest - k * records[f].v[t]);
      }
    }
    if (!options.parallel_stiffness || den == 0) break;
    k = num / den;
  }
  out.samples = total;
  return out;
}

std::vector<double> candidate_half_widths(const OperatorFitOptions& options) {
  std::vector<double> widths = options.half_widths;
  if (widths.empty()) {
    for (int i = 1; i <= 25; ++i) widths.push_back(0.02 * i);
  }
  return widths;
}

ExtendedFit best_half_width(const std::vector<DamperRecord>& records, const OperatorFitOptions& options) {
  ExtendedFit best;
  double best_sse = std::numeric_limits<double>::infinity();
  for (const double width : candidate_half_widths(options)) {
    const CurveAtWidth c = fit_curve_at_width(records, width, options);
    best.train_error_by_width.emplace_back(width, std::sqrt(c.squared_error / static_cast<double>(c.samples)));
    if (c.squared_error < best_sse) {
      best_sse = c.squared_error;
      best.half_width = width;
      best.curve = c.curve;
      best.stiffness = c.stiffness;
    }
  }
  return best;
}

ExtendedFit fit_extended(const std::vector<DamperRecord>& train, const OperatorFitOptions& options) {
  require_training(train);
  ExtendedFit best = best_half_width(train, options);
  best.fit_train = mean_fit(*best.make(), train);
  return best;
}

}  // namespace lashid::sim
