// Words and JSON for a Diagnosis.
#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "lashid/sim/diagnosis.hpp"

namespace lashid::sim {

namespace {

std::string p_text(double p) { return p < 1e-16 ? "p < 1e-16" : fmt::format("p = {:.2g}", p); }

// Lags (>= 1 for the autocorrelation) whose correlation leaves the band, strongest first, at most 4.
std::string outside_band(const std::vector<double>& r, int first_lag, int lag_offset, double band) {
  std::vector<std::pair<double, int>> out;
  for (std::size_t i = 0; i < r.size(); ++i) {
    const int lag = static_cast<int>(i) - lag_offset;
    if (lag >= first_lag && std::abs(r[i]) > band) out.emplace_back(std::abs(r[i]), lag);
  }
  std::sort(out.rbegin(), out.rend());
  std::string text;
  for (std::size_t i = 0; i < out.size() && i < 4; ++i) {
    const int lag = out[i].second;
    text += fmt::format("{}r({}) = {:+.3f}", i ? ", " : "", lag,
                        r[static_cast<std::size_t>(lag + lag_offset)]);
  }
  return text;
}

// Lag k (|k| <= 5) maximising the correlation of the measured and simulated increments on val: k > 0 means the
// simulation leads (its move at t matches the measurement's at t + k).
int simulation_lead(const Diagnosis& d) {
  const auto& y = d.val_measured;
  const auto& s = d.val_nominal;
  int best_lag = 0;
  double best = -std::numeric_limits<double>::infinity();
  for (int k = -5; k <= 5; ++k) {
    double sum = 0;
    for (std::size_t t = 6; t + 6 < y.size(); ++t) {
      const auto tk = static_cast<std::size_t>(static_cast<std::ptrdiff_t>(t) + k);
      sum += (y[tk] - y[tk - 1]) * (s[t] - s[t - 1]);
    }
    if (sum > best) {
      best = sum;
      best_lag = k;
    }
  }
  return best_lag;
}

// Share of the val simulation error within 10 samples after a reversal of the input's direction, and whether
// the measurement moved more (or less) than the simulation there.
struct ReversalError {
  double error_share = 0, sample_share = 0, measured_move = 0, simulated_move = 0;
};
ReversalError reversal_error(const Diagnosis& d) {
  ReversalError r;
  const auto& v = d.val_v;
  double total = 0, near = 0;
  std::size_t near_samples = 0, window_left = 0;
  int last_direction = 0;
  for (std::size_t t = 1; t < v.size(); ++t) {
    const int direction = v[t] > v[t - 1] ? 1 : v[t] < v[t - 1] ? -1 : 0;
    if (direction != 0) {
      if (last_direction != 0 && direction != last_direction) {
        window_left = 10;
        r.measured_move += std::abs(d.val_measured[std::min(t + 5, v.size() - 1)] - d.val_measured[t - 1]);
        r.simulated_move += std::abs(d.val_nominal[std::min(t + 5, v.size() - 1)] - d.val_nominal[t - 1]);
      }
      last_direction = direction;
    }
    const double e = d.val_measured[t] - d.val_nominal[t];
    total += e * e;
    if (window_left > 0) {
      near += e * e;
      ++near_samples;
      --window_left;
    }
  }
  r.error_share = total > 0 ? near / total : 0;
  r.sample_share = static_cast<double>(near_samples) / static_cast<double>(v.size());
  return r;
}

}  // namespace

std::vector<std::string> describe_findings(const Diagnosis& d) {
  std::vector<std::string> f;
  f.push_back(fmt::format("The nominal model ({}, n = {}, joint DIS+AIS least squares) simulates 'val' with a fit of "
                          "{:.1f} %.",
                          to_string(d.nominal.structure.op), d.nominal.n, d.fit_nominal));
  const auto& id = d.identification;
  if (id.whiteness.p_value >= 1e-4) {
    f.push_back(fmt::format("Its one-step residuals on the identification phases are white (Ljung-Box Q = {:.1f}, "
                            "{} lags, {}).",
                            id.whiteness.statistic, id.whiteness.dof, p_text(id.whiteness.p_value)));
  } else {
    f.push_back(fmt::format("Its one-step residuals on the identification phases are not white (Ljung-Box Q = {:.0f}, "
                            "{} lags, {}): {} (99 % band +-{:.3f}).",
                            id.whiteness.statistic, id.whiteness.dof, p_text(id.whiteness.p_value),
                            outside_band(id.autocorrelation, 1, 0, id.band), id.band));
  }
  if (id.independence.p_value < 1e-4) {
    f.push_back(fmt::format("They are correlated with the input (test statistic {:.0f}, {}): {}.",
                            id.independence.statistic, p_text(id.independence.p_value),
                            outside_band(id.cross_correlation, -kResidualLags, kResidualLags, id.band)));
  }
  if (d.remark3b_z > 4) {
    f.push_back(fmt::format("DIS and AIS disagree on A(q^-1) by {:.1f} standard errors (Remark 3b): the plant is not "
                            "the assumed operator followed by the assumed linear block.",
                            d.remark3b_z));
  } else {
    f.push_back(fmt::format("DIS and AIS agree on A(q^-1) (largest difference {:.1f} standard errors, Remark 3b).",
                            d.remark3b_z));
  }
  if (id.trend.p_value < 1e-4) {
    f.push_back(fmt::format("The residuals trend over the recording ({:+.3g} per 1000 samples, t = {:.1f}): the "
                            "output's offset drifts.",
                            1000 * id.trend.slope, id.trend.t));
  }
  const int lead = simulation_lead(d);
  if (lead > 0) {
    f.push_back(fmt::format("On 'val' the simulated response leads the measurement by {} sample{}.", lead,
                            lead > 1 ? "s" : ""));
  } else if (lead < 0) {
    f.push_back(fmt::format("On 'val' the simulated response lags the measurement by {} sample{}.", -lead,
                            lead < -1 ? "s" : ""));
  }
  const ReversalError rev = reversal_error(d);
  if (rev.error_share > 1.5 * rev.sample_share) {
    const bool measurement_moves = rev.measured_move > rev.simulated_move;
    f.push_back(fmt::format("{:.0f} % of the 'val' error lies within 10 samples after a reversal of the input "
                            "({:.0f} % of the samples): after a reversal the simulation {} while the measurement {}.",
                            100 * rev.error_share, 100 * rev.sample_share, measurement_moves ? "stays" : "jumps",
                            measurement_moves ? "jumps" : "stays"));
  }
  for (const CandidateCause& c : d.candidates) {
    if (!c.model.ok) {
      f.push_back(fmt::format("{}: not fitted ({}).", to_string(c.cause), c.model.failure));
      continue;
    }
    std::string evidence;
    if (c.cause == Cause::kOperatorType) {
      evidence = fmt::format("val error energy x{:.2f} of the nominal", c.statistic);
    } else if (c.cause == Cause::kColoredNoise) {
      evidence = fmt::format("instrumental variables; nominal residual whiteness {}", p_text(id.whiteness.p_value));
    } else {
      evidence = fmt::format("likelihood ratio {:.1f} ({}), extended residuals whiteness {}", c.statistic,
                             p_text(c.p_value), p_text(c.identification.whiteness.p_value));
    }
    f.push_back(fmt::format("{} {}: {}; val fit {:.1f} %.", to_string(c.cause), c.parameters.dump(), evidence,
                            c.fit_val));
  }
  if (d.cause == Cause::kNone) {
    f.push_back("Conclusion: none. The nominal model explains the data; no extension is supported by the evidence.");
  } else {
    f.push_back(fmt::format("Conclusion: {} {}. Val fit {:.1f} % (nominal) -> {:.1f} % (extended).", to_string(d.cause),
                            d.parameters.dump(), d.fit_nominal, d.fit_extended));
  }
  return f;
}

nlohmann::json to_json(const JointModel& m) {
  return {{"operator", to_string(m.structure.op)},
          {"input_lag", m.structure.input_lag},
          {"delay", m.structure.delay},
          {"drift", m.structure.drift},
          {"estimator", m.structure.instrumental ? "instrumental_variables" : "least_squares"},
          {"n", m.n},
          {"a", m.a},
          {"b", m.b},
          {"descending_border", {{"v", m.descending_v}, {"u", m.descending_u}}},
          {"ascending_border", {{"v", m.ascending_v}, {"u", m.ascending_u}}},
          {"kappa0", m.kappa0},
          {"kappa1", m.kappa1},
          {"residual_variance", m.residual_variance},
          {"rows", m.rows},
          {"parameters", m.parameters},
          {"rank_one_ratio", m.rank_one_ratio}};
}

namespace {

nlohmann::json to_json(const stats::PortmanteauTest& t) {
  return {{"statistic", t.statistic}, {"dof", t.dof}, {"p_value", t.p_value}};
}

nlohmann::json to_json(const ResidualAnalysis& r) {
  return {{"samples", r.samples},
          {"autocorrelation", r.autocorrelation},
          {"cross_correlation_lags", nlohmann::json::array({-kResidualLags, kResidualLags})},
          {"cross_correlation", r.cross_correlation},
          {"band_99", r.band},
          {"ljung_box", to_json(r.whiteness)},
          {"input_cross_correlation_test", to_json(r.independence)},
          {"trend", {{"slope", r.trend.slope}, {"t", r.trend.t}, {"p_value", r.trend.p_value}}}};
}

}  // namespace

nlohmann::json to_json(const Diagnosis& d) {
  nlohmann::json candidates = nlohmann::json::array();
  for (const CandidateCause& c : d.candidates) {
    nlohmann::json j = {{"cause", to_string(c.cause)}, {"parameters", c.parameters}, {"fitted", c.model.ok}};
    if (c.model.ok) {
      j["statistic"] = c.statistic;
      j["statistic_kind"] = c.cause == Cause::kOperatorType   ? "val_sse_ratio"
                            : c.cause == Cause::kColoredNoise ? "none"
                                                              : "likelihood_ratio";
      j["p_value"] = c.p_value;
      j["likelihood_ratio"] = c.likelihood_ratio;
      j["fit_val"] = c.fit_val;
      j["residual_whiteness_p"] = c.identification.whiteness.p_value;
      j["residual_variance"] = c.model.residual_variance;
    } else {
      j["failure"] = c.model.failure;
    }
    candidates.push_back(std::move(j));
  }
  return {{"cause", to_string(d.cause)},
          {"parameters", d.parameters},
          {"fit_nominal", d.fit_nominal},
          {"fit_extended", d.fit_extended},
          {"findings", d.findings},
          {"evidence",
           {{"identification_residuals", to_json(d.identification)},
            {"validation_residuals", to_json(d.validation)},
            {"remark3b_z", d.remark3b_z},
            {"candidates", std::move(candidates)}}},
          {"models", {{"nominal", to_json(d.nominal)}, {"extended", to_json(d.extended)}}},
          {"paper_estimates", {{"dis", to_json(d.dis)}, {"ais", to_json(d.ais)}}}};
}

}  // namespace lashid::sim
