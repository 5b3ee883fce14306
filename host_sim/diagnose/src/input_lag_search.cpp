// The input lag's lambda and its border model (search_input_lag, diagnosis_candidates.hpp).
#include <algorithm>
#include <array>
#include <cmath>
#include <exception>
#include <future>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

#include "diagnosis_candidates.hpp"
#include "two_threads.hpp"

namespace lashid::sim::detail {

namespace {

// A fit whose RSS is more than this many times a neighbouring lambda's is taken for a poor fixed point of a
// backlash's regime iteration (repair_path).
constexpr double kPoorFixedPoint = 1.1;

double rss_or_infinity(const JointModel& m) { return m.ok ? m.rss : std::numeric_limits<double>::infinity(); }

// Golden-section search of lambda in [a, b] at a given border resolution; returns the best fit seen (or `best`).
template <class Fit>
JointModel golden_lambda(Fit fit, double a, double b, int iterations, JointModel best) {
  const double g = (std::sqrt(5.0) - 1.0) / 2.0;
  for (int it = 0; it < iterations; ++it) {
    const double x1 = b - g * (b - a), x2 = a + g * (b - a);
    JointModel m1 = fit(x1), m2 = fit(x2);
    const double r1 = rss_or_infinity(m1), r2 = rss_or_infinity(m2);
    if (r1 < r2) {
      b = x2;
      if (r1 < rss_or_infinity(best)) best = std::move(m1);
    } else {
      a = x1;
      if (r2 < rss_or_infinity(best)) best = std::move(m2);
    }
  }
  return best;
}

// Cross-validation within val: fold k is trained on the identification phases and one half of val (relabelled as
// identification data) and scored by simulating the other half.
struct ValFolds {
  std::array<FlatRecording, 2> train;
  std::array<std::pair<std::size_t, std::size_t>, 2> held_out;
};

ValFolds val_folds(const FlatRecording& data, std::pair<std::size_t, std::size_t> val) {
  const std::size_t mid = val.first + (val.second - val.first) / 2;
  ValFolds f{{data, data}, {std::pair{mid, val.second}, std::pair{val.first, mid}}};
  for (std::size_t t = val.first; t < mid; ++t) f.train[0].phase[t] = Phase::kAis;
  for (std::size_t t = mid; t < val.second; ++t) f.train[1].phase[t] = Phase::kAis;
  return f;
}

// Fold k's simulation error on its held-out half and that half's energy about its own mean; {inf, 1} if the fold
// fails or its simulation diverges. The fold starts from `start`'s regimes; its model is kept as a start for the
// restarts (search_input_lag), without its residuals (a start's residuals are never read).
struct HeldOutError {
  double error = std::numeric_limits<double>::infinity();
  double total = 1.0;
};

template <class Fit>
HeldOutError held_out_error(Fit fit, double lambda, const JointModel& start, const ValFolds& folds, std::size_t k,
                            const FlatRecording& data, JointModel& fold) {
  fold = fit(lambda, &start, folds.train[k]);
  fold.residuals = {};
  fold.residual_t = {};
  if (!fold.ok) return {};
  const auto [begin, end] = folds.held_out[k];
  const std::vector<double> sim = simulate_segment(fold, data, begin, end);
  double mean = 0;
  for (std::size_t t = begin; t < end; ++t) mean += data.y[t];
  mean /= static_cast<double>(end - begin);
  HeldOutError h{0.0, 0.0};
  for (std::size_t t = begin; t < end; ++t) {
    const double e = data.y[t] - sim[t - begin];
    if (!std::isfinite(e)) return {};
    h.error += e * e;
    h.total += (data.y[t] - mean) * (data.y[t] - mean);
  }
  return h;
}

// One fit per lambda along a path: each starts from the previous lambda's regimes (continuation) and, for a
// backlash, also from `current`'s, keeping the lower RSS. Started from `current` alone, a backlash's regime
// iteration ends in a poor fixed point at some lambdas (RSS 3 to 50 times the neighbours' on tuning seeds).
struct LagPath {
  std::vector<double> lambda;
  std::vector<JointModel> model;
  std::vector<double> fit_val;
  std::vector<double> fit_cross;
  /// Whether model[i] is the fit started from model[i - 1] as it now stands: fitting it again from there would
  /// repeat that fit (repair_path skips it).
  std::vector<char> from_previous;
  /// The fold models of the points cross_validate fitted (as starts: without residuals), and which those are.
  std::vector<std::array<JointModel, 2>> fold;
  std::vector<char> cross_validated;
};

std::size_t best_rss(const LagPath& p) {
  std::size_t best = 0;
  for (std::size_t i = 1; i < p.model.size(); ++i) {
    if (p.model[i].rss < p.model[best].rss) best = i;
  }
  return best;
}

// A backlash's regime iteration can end in a poor fixed point even from the previous lambda's regimes (RSS 5 to 10
// times both neighbours' on tuning seeds 1067 and 1075). The RSS of the best fit is continuous in lambda, so,
// outward from the path's RSS minimum, a point whose RSS is more than kPoorFixedPoint times its inner neighbour's
// is fitted again from that neighbour's regimes, and the lower RSS kept (tuning seed 1099: lambda 0.37 -> 0.45,
// true 0.466). Starting such a point from the switch's regimes as well changed no answer on the tuning seeds.
template <class Fit>
void repair_path(Fit fit, LagPath& path, const FlatRecording& data, std::pair<std::size_t, std::size_t> val) {
  const std::size_t count = path.model.size();
  if (count < 2) return;
  const std::size_t best = best_rss(path);
  // Returns whether model[i] was replaced.
  const auto repair = [&](std::size_t i, std::size_t inner) {
    if (!(path.model[i].rss > kPoorFixedPoint * path.model[inner].rss)) return false;
    JointModel again = fit(path.lambda[i], &path.model[inner], data);
    if (!again.ok || !(again.rss < path.model[i].rss)) return false;
    path.model[i] = std::move(again);
    path.fit_val[i] = simulation_fit(path.model[i], data, val.first, val.second);
    return true;
  };
  // The two directions are independent: one on each thread. Upward, a point fitted from its inner neighbour as it
  // stands is not fitted again from it (the same fit: it could not lower the RSS); a replaced point's outer
  // neighbour was fitted from the point before it changed. Downward, the path's fits ran the other way.
  on_two_threads(2, [&](std::size_t upward) {
    if (upward != 0) {
      for (std::size_t i = best + 1; i < count; ++i) {
        if (path.from_previous[i] == 0 && repair(i, i - 1) && i + 1 < count) path.from_previous[i + 1] = 0;
      }
    } else {
      for (std::size_t i = best; i-- > 0;) repair(i, i + 1);
    }
  });
}

// fit(lambdas[i], start, data) for every i, on two threads: for fits that do not depend on each other.
template <class Fit>
std::vector<JointModel> fit_independent(Fit fit, const JointModel* start, const std::vector<double>& lambdas,
                                        const FlatRecording& data) {
  std::vector<JointModel> fits(lambdas.size());
  on_two_threads(lambdas.size(), [&](std::size_t i) { fits[i] = fit(lambdas[i], start, data); });
  return fits;
}

template <class Fit>
LagPath fit_lag_path(Fit fit, const JointModel& current, const std::vector<double>& lambdas, const FlatRecording& data,
                     std::pair<std::size_t, std::size_t> val, bool two_starts) {
  LagPath path;
  const auto add = [&](JointModel m, double lambda, bool from_previous) {
    path.lambda.push_back(lambda);
    path.fit_val.push_back(simulation_fit(m, data, val.first, val.second));
    path.fit_cross.push_back(-std::numeric_limits<double>::infinity());
    path.from_previous.push_back(from_previous ? 1 : 0);
    path.model.push_back(std::move(m));
  };
  if (current.structure.op == OperatorKind::kSwitch) {
    // A switch has no regimes to carry along the path: its fit does not depend on the start (fit_joint_model starts
    // only a backlash from `initial`), so the path's points are independent.
    std::vector<JointModel> fits = fit_independent(fit, &current, lambdas, data);
    for (std::size_t i = 0; i < fits.size(); ++i) {
      if (fits[i].ok) add(std::move(fits[i]), lambdas[i], false);
    }
    return path;
  }
  // The second start's fits (from `current`, at every lambda but the first) do not depend on the path: a second
  // thread runs them ahead while this one follows the path, each taken as the path reaches its lambda.
  std::vector<std::promise<JointModel>> from_current(two_starts ? lambdas.size() : 0);
  std::future<void> ahead;
  if (two_starts && lambdas.size() > 1) {
    ahead = std::async(std::launch::async, [&] {
      for (std::size_t i = 1; i < lambdas.size(); ++i) {
        try {
          from_current[i].set_value(fit(lambdas[i], &current, data));
        } catch (...) {  // passed on to the path, which would otherwise wait for it for good
          from_current[i].set_exception(std::current_exception());
        }
      }
    });
  }
  const JointModel* previous = &current;
  for (std::size_t i = 0; i < lambdas.size(); ++i) {
    const double lambda = lambdas[i];
    JointModel m = fit(lambda, previous, data);
    bool from_previous = previous != &current;
    // From the second lambda on: the fit from the previous lambda's regimes, or the one from `current`'s if its
    // RSS is lower (the first is itself from `current`: previous is `current` there).
    if (two_starts && i > 0) {
      JointModel again = from_current[i].get_future().get();
      if (again.ok && (!m.ok || again.rss < m.rss)) {
        m = std::move(again);
        from_previous = false;
      }
    }
    if (!m.ok) continue;
    add(std::move(m), lambda, from_previous);
    previous = &path.model.back();
  }
  if (two_starts && current.structure.op == OperatorKind::kBacklash) repair_path(fit, path, data, val);
  return path;
}

// The lambda whose model simulates val best among those the identification phases do not reject: N ln(RSS /
// min_rss) <= window.
std::size_t best_val(const LagPath& p, double min_rss, double window) {
  std::size_t best = p.model.size();
  for (std::size_t i = 0; i < p.fit_val.size(); ++i) {
    const double lr = static_cast<double>(p.model[i].rows) * std::log(p.model[i].rss / min_rss);
    if (lr <= window && (best == p.model.size() || p.fit_val[i] > p.fit_val[best])) best = i;
  }
  return best;
}

// The lambda with the best cross-validated fit within val; p.model.size() if none is finite.
std::size_t best_cross(const LagPath& p) {
  std::size_t best = p.model.size();
  for (std::size_t i = 0; i < p.fit_cross.size(); ++i) {
    if (std::isfinite(p.fit_cross[i]) && (best == p.model.size() || p.fit_cross[i] > p.fit_cross[best])) best = i;
  }
  return best;
}

// The points of the path whose RSS is at most max_rss, cross-validated within val (each fold from the point's own
// model's regimes): the pooled simulation fit of the two held-out halves, 100 (1 - sqrt(sum of errors / sum of
// energies)); the others keep -infinity. The fold fits (point, fold) run on two threads.
template <class Fit>
void cross_validate(Fit fit, LagPath& path, const ValFolds& folds, const FlatRecording& data, double max_rss) {
  const std::size_t count = path.model.size();
  std::vector<std::size_t> points;
  for (std::size_t i = 0; i < count; ++i) {
    if (path.model[i].rss <= max_rss) points.push_back(i);
  }
  std::vector<std::array<HeldOutError, 2>> held_out(count);
  path.fold.assign(count, {});
  path.cross_validated.assign(count, 0);
  for (std::size_t i : points) path.cross_validated[i] = 1;
  on_two_threads(2 * points.size(), [&](std::size_t task) {
    const std::size_t i = points[task / 2], k = task % 2;
    held_out[i][k] = held_out_error(fit, path.lambda[i], path.model[i], folds, k, data, path.fold[i][k]);
  });
  for (std::size_t i = 0; i < count; ++i) {
    const double error = held_out[i][0].error + held_out[i][1].error;
    const double total = held_out[i][0].total + held_out[i][1].total;
    path.fit_cross[i] = std::isfinite(error) && total > 0 ? 100.0 * (1.0 - std::sqrt(error / total))
                                                          : -std::numeric_limits<double>::infinity();
  }
}

}  // namespace

// Input lag. Two border models:
// - coarse: borders linear between the experiment's abscissas; RSS(lambda) on a 0.05 grid, then golden section
//   (+-0.05). On borders linear between the levels it is exact and pins lambda sharply.
// - fine: options.lag_border_segments points per interval, held smooth by a prior where the data are thin. The lag
//   moves the operator's input between the levels, where a real border is curved, so lambda needs a border model
//   that is right there; but with a flexible border the identification phases barely tell lambda apart (every
//   pulse starts from the same extreme level: a different lambda and a reshaped border give the same outputs; the
//   RSS profile is flat to 1 % over +-0.15 on curved tuning seeds, and its minimum is biased upward). The val
//   phase, whose moves join every pair of levels, does tell them apart, but only where the borders are known
//   beside the levels, which the identification phases never visit: lambda is cross-validated within val (each
//   fold trained on the identification phases and one half of val, scored on the other half), on a 0.05 grid and
//   then a 0.01 grid (+-0.02) around the best point. The model returned is fitted on the identification phases
//   only. With options.lag_cross_validation off: the lambda whose model simulates val best within
//   options.lag_val_window of the RSS minimum (session 7's rule, biased upward on curved borders).
// The fine model is used if BIC prefers it at its RSS minimum (N ln(RSS_coarse / RSS_fine) > extra parameters x
// ln N) or if it simulates val more than options.lag_fine_val_gain points better than the coarse one; otherwise
// the coarse model (on borders linear between the levels it is exact and pins lambda better).
JointModel search_input_lag(const ExperimentConfig& config, const FlatRecording& data, const JointModel& current,
                            const DiagnosisOptions& options) {
  // Research only (DiagnosisOptions::regime_oracle): the known plant on the finer tables replaces every start there.
  std::optional<JointModel> oracle_start;
  if (options.regime_oracle && options.lag_border_segments > 1) {
    const DiagnosisOptions::KnownPlant& p = *options.regime_oracle;
    oracle_start = true_plant_on_tables(config, options.lag_border_segments, p.a, p.b, p.ascending, p.descending);
  }
  const auto fit_with = [&](int segments) {
    return [&, segments](double lambda, const JointModel* start, const FlatRecording& on) {
      ModelStructure s = current.structure;
      s.border_smoothness = options.lag_border_smoothness;
      s.input_lag = lambda;
      s.border_segments = segments;
      return fit_joint_model(config, on, s, segments > 1 && oracle_start ? &*oracle_start : start, true);
    };
  };
  const auto coarse = fit_with(1);
  const auto fine = fit_with(options.lag_border_segments);
  const double max_lag = options.max_input_lag;
  std::vector<double> grid;
  for (double lambda = 0.05; lambda <= max_lag + 1e-9; lambda += 0.05) grid.push_back(lambda);
  // The grid's fits are independent (each from `current`): on two threads. The best is then chosen in grid order,
  // as a single thread would.
  std::vector<JointModel> grid_fits = fit_independent(coarse, &current, grid, data);
  JointModel best_coarse;
  double grid_lambda = 0;
  for (std::size_t i = 0; i < grid.size(); ++i) {
    if (grid_fits[i].ok && grid_fits[i].rss < rss_or_infinity(best_coarse)) {
      best_coarse = std::move(grid_fits[i]);
      grid_lambda = grid[i];
    }
  }
  grid_fits.clear();
  if (!best_coarse.ok) return current;
  // The coarse model's golden section only where the coarse model is the answer (every fit costs about the same:
  // building the normal equations dominates, whatever the border resolution).
  const auto refined_coarse = [&]() {
    return golden_lambda([&](double l) { return coarse(l, &current, data); }, std::max(grid_lambda - 0.05, 0.0),
                         std::min(grid_lambda + 0.05, max_lag), options.golden_iterations, best_coarse);
  };
  if (options.lag_border_segments <= 1) return refined_coarse();
  const auto val = val_range(data);
  LagPath path = fit_lag_path(fine, current, grid, data, val, true);
  if (path.model.empty()) return refined_coarse();
  // Cross-validation only where the lag can matter: if no lambda's fit is significant against `current`, the
  // candidate is rejected whatever lambda it has (this keeps the lag's search as cheap as before for the other
  // causes, where it is a candidate in every round).
  const JointModel& fine_rss = path.model[best_rss(path)];
  const bool cross = options.lag_cross_validation && significant(likelihood_ratio(current, fine_rss), options);
  // The folds copy the recording: made only where they are used.
  const ValFolds folds = cross ? val_folds(data, val) : ValFolds{};
  const double min_rss = fine_rss.rss;
  const double max_cross_rss = options.lag_cross_validated_rss * min_rss;
  if (cross) cross_validate(fine, path, folds, data, max_cross_rss);
  const double samples = static_cast<double>(best_coarse.rows);
  const double gain = samples * std::log(best_coarse.rss / min_rss);
  const double cost = static_cast<double>(fine_rss.parameters - best_coarse.parameters) * std::log(samples);
  std::size_t at = cross ? best_cross(path) : best_val(path, min_rss, options.lag_val_window);
  if (at == path.model.size()) at = best_val(path, min_rss, options.lag_val_window);
  const double coarse_val = simulation_fit(best_coarse, data, val.first, val.second);
  if (!(gain > cost) && !(path.fit_val[at] > coarse_val + options.lag_fine_val_gain)) return refined_coarse();
  std::vector<double> local;
  for (int k = -2; k <= 2; ++k) {
    const double lambda = path.lambda[at] + 0.01 * k;
    if (k != 0 && lambda > 0.0 && lambda <= max_lag) local.push_back(lambda);
  }
  LagPath near = fit_lag_path(fine, path.model[at], local, data, val, false);
  if (cross) {
    cross_validate(fine, near, folds, data, max_cross_rss);
    const std::size_t near_at = best_cross(near);
    const bool on_path = near_at == near.model.size() || near.fit_cross[near_at] <= path.fit_cross[at];
    const LagPath& from = on_path ? path : near;
    const std::size_t point = on_path ? at : near_at;
    JointModel chosen = from.model[point];
    if (chosen.structure.op == OperatorKind::kBacklash) {
      // The folds' regimes may be a better start (val's data help to determine their borders): the fit is redone
      // on the identification phases from each, and the lowest RSS kept. A backlash's only (a switch has no
      // regimes to find); the two folds on two threads, each the cross-validation's own where it made one.
      const double lambda = chosen.structure.input_lag;
      const auto restart = [&](std::size_t k) {
        const JointModel fold =
            from.cross_validated[point] != 0 ? from.fold[point][k] : fine(lambda, &chosen, folds.train[k]);
        return fold.ok ? fine(lambda, &fold, data) : JointModel{};
      };
      std::array<JointModel, 2> restarted;
      on_two_threads(restarted.size(), [&](std::size_t k) { restarted[k] = restart(k); });
      for (JointModel& m : restarted) {
        if (m.ok && m.rss < chosen.rss) chosen = std::move(m);
      }
    }
    return chosen;
  }
  const std::size_t near_at = best_val(near, min_rss, options.lag_val_window);
  if (near_at == near.model.size() || near.fit_val[near_at] <= path.fit_val[at]) return path.model[at];
  return near.model[near_at];
}

}  // namespace lashid::sim::detail
