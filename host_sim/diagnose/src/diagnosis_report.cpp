// A Diagnosis in words: what the nominal simulation gets wrong and what the evidence says.
#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "lashid/diagnose/diagnosis.hpp"

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
                          "{}.",
                          to_string(d.nominal.structure.op), d.nominal.n, describe_fit(d.fit_nominal)));
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
  if (std::isnan(d.remark3b_z)) {
    f.push_back(fmt::format("DIS and AIS were not compared (Remark 3b): a scheme's estimate failed (DIS: {}, AIS: "
                            "{}).",
                            est::to_string(d.dis.status), est::to_string(d.ais.status)));
  } else if (d.remark3b_z > 4) {
    f.push_back(fmt::format("DIS and AIS disagree on A(q^-1), B(q^-1) by {:.1f} standard errors (Remark 3b): the "
                            "plant is not the assumed operator followed by the assumed linear block.",
                            d.remark3b_z));
  } else {
    f.push_back(fmt::format("DIS and AIS agree on A(q^-1), B(q^-1) (largest difference {:.1f} standard errors, "
                            "Remark 3b).",
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
      evidence = fmt::format("{}; nominal residual whiteness {}",
                             c.parameters.output_error ? "instrumental variables, then output error"
                                                       : "instrumental variables",
                             p_text(id.whiteness.p_value));
    } else {
      evidence = fmt::format("likelihood ratio {:.1f} ({}), extended residuals whiteness {}", c.statistic,
                             p_text(c.p_value), p_text(c.identification.whiteness.p_value));
    }
    f.push_back(fmt::format("{} {}: {}; val fit {}.", to_string(c.cause), to_string(c.parameters), evidence,
                            describe_fit(c.fit_val)));
  }
  if (!d.colored_check.white) {
    f.push_back(fmt::format("The final structure's identification residuals are not white: Ljung-Box Q / N = {:.4f}, "
                            "{:.4f} without their part that repeats with the pulse period (a model's own mismatch "
                            "repeats with the input, sensor noise does not).",
                            d.colored_check.correlation, d.colored_check.aperiodic_correlation));
  }
  if (d.cause == Cause::kNone) {
    f.push_back("Conclusion: none. The nominal model explains the data; no extension is supported by the evidence.");
  } else {
    std::string steps;
    for (const AddedCause& a : d.added) {
      steps += fmt::format("{}{} {} ({} -> {})", steps.empty() ? "" : ", then ", to_string(a.cause),
                           to_string(a.parameters), describe_fit(a.fit_before), describe_fit(a.fit_after));
    }
    f.push_back(fmt::format("Conclusion: {} cause{}, strongest first: {}. Val fit {} (nominal) -> {} (extended).",
                            d.added.size(), d.added.size() > 1 ? "s" : "", steps, describe_fit(d.fit_nominal),
                            describe_fit(d.fit_extended)));
  }
  return f;
}

std::string describe_fit(double fit_percent) {
  if (!std::isfinite(fit_percent)) return "none (its simulation diverges)";
  if (fit_percent < -999.0) return "below -999 % (its simulation runs away)";
  return fmt::format("{:.1f} %", fit_percent);
}

std::string to_string(const CauseParameters& p) {
  nlohmann::json j = nlohmann::json::object();
  if (p.lambda) j["lambda"] = *p.lambda;
  if (p.delay) j["delay"] = *p.delay;
  if (p.drift_total) j["drift_total"] = *p.drift_total;
  if (p.instrumental_variables) j["estimator"] = p.output_error ? "output_error" : "instrumental_variables";
  if (p.op) j["operator"] = to_string(*p.op);
  return j.dump();
}

}  // namespace lashid::sim
