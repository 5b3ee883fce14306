#include "lashid/report/json.hpp"

#include <utility>

#include "lashid/report/border_check.hpp"

namespace lashid::sim {

nlohmann::json to_json(const SchemeResult& r) {
  nlohmann::json out = {{"a", r.a},
                        {"b", r.b},
                        {"F", r.F},
                        {"theta", r.theta},
                        {"c", r.c},
                        {"F_centered", r.F_centered},
                        {"theta_std_error", r.theta_std_error},
                        {"ybar0", r.ybar0},
                        {"held_output", r.held_output},
                        {"noise_variance", r.noise_variance},
                        {"rcond", r.rcond},
                        {"rows", r.rows},
                        {"status", est::to_string(r.status)}};
  // Without a solution the estimates are null, not the zeros they were initialised to: a reader that skips
  // "status" must not take them for values. The step experiment's mean (ybar0) does not need the solution.
  if (r.status != est::Status::kOk) {
    for (const char* key : {"a", "b", "F", "theta", "c", "F_centered", "theta_std_error", "noise_variance"}) {
      out[key] = nullptr;
    }
  }
  return out;
}

nlohmann::json to_json(const SchemeResult& r, const ExperimentConfig& config) {
  nlohmann::json out = to_json(r);
  // The status is the least squares' (a solution exists); whether the pulses moved the output at all is this test
  // (border_check.hpp, docs/data-format.md), with its warnings by name.
  const report::BorderCheck check = report::check_border(config, r);
  nlohmann::json warnings = nlohmann::json::array();
  if (check.applicable) {
    // max_z is infinite (null in JSON) for a noise-free fit whose groups differ.
    out["border_check"] = {{"alpha", report::kFlatBorderAlpha},
                           {"max_z", check.max_z},
                           {"threshold", check.threshold},
                           {"flat", check.flat}};
    if (check.flat) warnings.push_back("border_not_distinguishable_from_flat");
  }
  out["warnings"] = std::move(warnings);
  return out;
}

nlohmann::json to_json(const JointModel& m) {
  return {{"operator", to_string(m.structure.op)},
          {"input_lag", m.structure.input_lag},
          {"delay", m.structure.delay},
          {"drift", m.structure.drift},
          {"border_segments", m.structure.border_segments},
          {"estimator", m.structure.instrumental
                            ? (m.structure.output_error ? "output_error" : "instrumental_variables")
                            : "least_squares"},
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
    nlohmann::json j = {{"cause", to_string(c.cause)}, {"parameters", to_json(c.parameters)}, {"fitted", c.model.ok}};
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
  nlohmann::json causes = nlohmann::json::array();
  for (Cause c : d.causes) causes.push_back(to_string(c));
  nlohmann::json added = nlohmann::json::array();
  for (const AddedCause& a : d.added) {
    added.push_back({{"cause", to_string(a.cause)},
                     {"parameters", to_json(a.parameters)},
                     {"likelihood_ratio", a.likelihood_ratio},
                     {"fit_before", a.fit_before},
                     {"fit_after", a.fit_after},
                     {"gain", a.fit_after - a.fit_before},
                     {"ljung_box_before", a.ljung_box_before},
                     {"ljung_box_after", a.ljung_box_after}});
  }
  return {{"cause", to_string(d.cause)},
          {"causes", std::move(causes)},
          {"parameters", to_json(d.parameters)},
          {"gain_per_cause", std::move(added)},
          {"fit_nominal", d.fit_nominal},
          {"fit_extended", d.fit_extended},
          {"findings", d.findings},
          {"evidence",
           {{"identification_residuals", to_json(d.identification)},
            {"validation_residuals", to_json(d.validation)},
            {"remark3b_z", d.remark3b_z},
            {"colored_noise_check",
             {{"white", d.colored_check.white},
              {"ljung_box_per_sample", d.colored_check.correlation},
              {"aperiodic_ljung_box_per_sample", d.colored_check.aperiodic_correlation}}},
            {"candidates", std::move(candidates)}}},
          {"models", {{"nominal", to_json(d.nominal)}, {"extended", to_json(d.extended)}}},
          {"paper_estimates", {{"dis", to_json(d.dis)}, {"ais", to_json(d.ais)}}}};
}

nlohmann::json to_json(const CauseParameters& p) { return nlohmann::json::parse(to_string(p)); }

}  // namespace lashid::sim
