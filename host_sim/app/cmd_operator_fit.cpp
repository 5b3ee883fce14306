// `lashid operator-fit`: the paper's operators and the friction-gap extension against measured damper data
// (docs/friction-damper.md).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "lashid/identify/identify.hpp"
#include "lashid/io/config.hpp"
#include "lashid/io/files.hpp"
#include "lashid/operator_fit/damper_causes.hpp"
#include "lashid/operator_fit/operator_fit.hpp"
#include "lashid/operator_fit/output_dynamics.hpp"
#include "lashid/report/json.hpp"
#include "lashid/report/plot.hpp"
#include "lashid/report/report.hpp"
#include "lashid/sim/scenario.hpp"

namespace lashid::app {

using namespace lashid::sim;
using nlohmann::json;

namespace {

std::vector<DamperRecord> load(const std::vector<std::string>& files, int factor) {
  std::vector<DamperRecord> out;
  for (const auto& f : files) out.push_back(decimate(read_damper_csv(f), factor));
  return out;
}

json table_json(const std::vector<std::pair<double, double>>& table) {
  json out = json::array();
  for (const auto& [x, y] : table) out.push_back({x, y});
  return out;
}

json border_json(const Border& border, int points) {
  std::vector<std::pair<double, double>> table;
  for (int i = 0; i < points; ++i) {
    const double v = border.lo() + (border.hi() - border.lo()) * i / (points - 1);
    table.emplace_back(v, border(v));
  }
  return table_json(table);
}

json analysis_json(const LoopAnalysis& a) {
  json phases = json::object();
  for (const auto& p : a.phases) {
    phases[p.phase] = {{"samples", p.samples}, {"share_of_squared_error", p.share_of_squared_error}, {"rms", p.rms}};
  }
  return {{"phases", phases},
          {"reversals", a.reversals},
          {"plateau", a.plateau},
          {"measured_reversal_slope", a.measured_reversal_slope},
          {"simulated_reversal_slope", a.simulated_reversal_slope},
          {"measured_gap", a.measured_gap},
          {"simulated_gap", a.simulated_gap},
          {"measured_gap_centre_spread", a.measured_gap_centre_spread},
          {"peak_speed", a.peak_speed}};
}

void print_analysis(const std::string& model, const LoopAnalysis& a, std::size_t n, const LoopPhaseOptions& o) {
  fmt::print("  {} model, error by phase of the loop ({} reversals):\n", model, a.reversals);
  for (const auto& p : a.phases) {
    fmt::print("    {:<11} {:5.1f} % of the samples, {:5.1f} % of the squared error, RMS {:.3f}\n", p.phase,
               100.0 * static_cast<double>(p.samples) / static_cast<double>(n), 100.0 * p.share_of_squared_error,
               p.rms);
  }
  const auto worst = std::max_element(a.phases.begin(), a.phases.end(), [](const auto& x, const auto& y) {
    return x.share_of_squared_error < y.share_of_squared_error;
  });
  fmt::print("    In words: {:.0f} % of the squared error is in the {} phase. Over the first {} of travel after a "
             "reversal the measured force changes at {:.1f} per unit of v, the simulation at {:.1f}; per half-cycle "
             "the measured force stays below 10 % of the friction level ({:.2f}) for {:.3f} of travel, the "
             "simulated one for {:.3f}.\n",
             100.0 * worst->share_of_squared_error, worst->phase, o.reversal_window, a.measured_reversal_slope,
             a.simulated_reversal_slope, a.plateau, a.measured_gap, a.simulated_gap);
}

json causes_json(const std::vector<DamperCause>& causes) {
  json out = json::array();
  for (const auto& c : causes) {
    out.push_back({{"name", c.name}, {"in_extended_model", c.in_extended_model}, {"evidence", c.evidence}});
  }
  return out;
}

void print_causes(const std::vector<DamperCause>& causes) {
  fmt::print("\nCauses supported by the errors on the test files:\n");
  for (const auto& c : causes) {
    fmt::print("  - {} ({}): {}\n", c.name, c.in_extended_model ? "in the extended model" : "not modelled",
               c.evidence);
  }
}

json run_identification(const HysteresisOperator& actuator, double v_min, double v_max) {
  const Scenario scenario = actuator_scenario(actuator, v_min, v_max, 1e-4);
  SimulationOptions options;
  options.seed = 1;
  const Recording rec = simulate(scenario, options);
  json out = {{"scenario", scenario.description}, {"config", to_json(scenario.config)}};
  fmt::print("\nDIS/AIS with the fitted {} model as the actuator ({}):\n", actuator.name(), scenario.description);
  for (const auto scheme : {est::Scheme::kDescending, est::Scheme::kAscending}) {
    const SchemeResult r = identify_scheme(scenario.config, rec, scheme, IdentifyOptions{}, scenario.name);
    report::print_scheme_result(scenario.config, r);
    out[scheme == est::Scheme::kDescending ? "dis" : "ais"] = to_json(r);
  }
  return out;
}

// What the models do on the test files, one entry per file in the order of the files.
struct TestResults {
  json fit_nominal = json::object();   // file -> fit (%)
  json fit_extended = json::object();  // file -> fit (%)
  json fit_dynamics = json::object();  // file -> fit (%) of the extended operator followed by B/A
  json loops = json::object();         // file -> the three loop analyses
  std::vector<LoopAnalysis> nominal;
  std::vector<LoopAnalysis> extended;
  TestErrors errors;  // squared errors of the extended model without and with the dynamics, summed over the files
};

// Simulates the three models on every test file, prints their fits and loop analyses, and adds one panel per file.
TestResults evaluate_test_files(const std::vector<DamperRecord>& test, const NominalFit& nominal,
                                const HysteresisOperator& nominal_op, const HysteresisOperator& extended_op,
                                const OutputFilter& dynamics, double rate, const LoopPhaseOptions& phase_options,
                                report::plot::Figure& figure) {
  TestResults out;
  for (const auto& rec : test) {
    const auto u_nom = simulate_operator(nominal_op, rec.v, rec.u.front());
    const auto u_ext = simulate_operator(extended_op, rec.v, rec.u.front());
    const auto u_dyn = dynamics.apply(u_ext, rec.u.front());
    const double f_nom = fit_to_record(rec, u_nom), f_ext = fit_to_record(rec, u_ext);
    const double f_dyn = fit_to_record(rec, u_dyn);
    out.fit_nominal[rec.source] = f_nom;
    out.fit_extended[rec.source] = f_ext;
    out.fit_dynamics[rec.source] = f_dyn;
    for (std::size_t t = 0; t < rec.u.size(); ++t) {
      out.errors.extended += (rec.u[t] - u_ext[t]) * (rec.u[t] - u_ext[t]);
      out.errors.with_dynamics += (rec.u[t] - u_dyn[t]) * (rec.u[t] - u_dyn[t]);
    }
    out.errors.mean_fit_extended += f_ext / static_cast<double>(test.size());
    out.errors.mean_fit_dynamics += f_dyn / static_cast<double>(test.size());
    fmt::print("{}: {} samples, test fit nominal ({}) {:.1f} %, extended {:.1f} %, extended + dynamics {:.1f} %\n",
               rec.source, rec.v.size(), nominal.chosen, f_nom, f_ext, f_dyn);
    const LoopAnalysis a_nom = analyse_loop(rec, u_nom, phase_options);
    const LoopAnalysis a_ext = analyse_loop(rec, u_ext, phase_options);
    const LoopAnalysis a_dyn = analyse_loop(rec, u_dyn, phase_options);
    print_analysis("nominal", a_nom, rec.v.size(), phase_options);
    print_analysis("extended", a_ext, rec.v.size(), phase_options);
    print_analysis("extended + dynamics", a_dyn, rec.v.size(), phase_options);
    // What the extended operator still gets wrong: how much of its error is fast oscillation (chatter or ringing).
    const ErrorOscillation osc = error_oscillation(rec.u, u_ext, rate);
    // If that fast part stayed and everything else were right: ||e_fast|| = sqrt(share) ||e||, so the fit would be
    // 100 - sqrt(share) (100 - fit). A ceiling for any model that cannot predict the oscillation's phase.
    const double ceiling = 100 - std::sqrt(osc.fast_share) * (100 - f_ext);
    fmt::print("  Extended model's error: {:.0f} % of its energy changes faster than about 10 Hz (the error minus "
               "its 100 ms moving mean), with the largest amplitude, {:.3f}, at {:.0f} Hz; a model that still "
               "misses that fast part fits at most {:.1f} %\n",
               100 * osc.fast_share, osc.peak_amplitude, osc.peak_hz, ceiling);
    out.nominal.push_back(a_nom);
    out.extended.push_back(a_ext);
    out.loops[rec.source] = {{"nominal", analysis_json(a_nom)},
                             {"extended", analysis_json(a_ext)},
                             {"extended_dynamics", analysis_json(a_dyn)},
                             {"extended_error_oscillation",
                              {{"fast_share", osc.fast_share},
                               {"peak_hz", osc.peak_hz},
                               {"peak_amplitude", osc.peak_amplitude},
                               {"fit_ceiling_without_it", ceiling}}}};
    figure.panels.push_back({std::filesystem::path(rec.source).filename().string(), "displacement v", "force u",
                             {{"measured", rec.v, rec.u},
                              {fmt::format("{} (nominal), fit {:.1f} %", nominal.chosen, f_nom), rec.v, u_nom},
                              {fmt::format("friction_gap, fit {:.1f} %", f_ext), rec.v, u_ext},
                              {fmt::format("friction_gap + B/A, fit {:.1f} %", f_dyn), rec.v, u_dyn}}});
  }
  return out;
}

// Sampling rate of the (possibly decimated) training records: samples per second over the first file's span.
double sampling_rate(const std::vector<DamperRecord>& train) {
  const DamperRecord& r = train.front();
  return static_cast<double>(r.t.size() - 1) / (r.t.back() - r.t.front());
}

// The filter after the extended operator, from the training files only: input the operator's simulation, output
// the measured force.
OutputDynamicsFit fit_dynamics(const std::vector<DamperRecord>& train, const HysteresisOperator& extended_op) {
  std::vector<FilterData> data;
  for (const auto& rec : train) data.push_back({simulate_operator(extended_op, rec.v, rec.u.front()), rec.u});
  return fit_output_dynamics(data);
}

json pole_json(const FilterPole& p) {
  return {{"re", p.z.real()},           {"im", p.z.imag()},           {"magnitude", std::abs(p.z)},
          {"natural_hz", p.natural_hz}, {"damped_hz", p.damped_hz}, {"zeta", p.zeta}};
}

json dynamics_json(const OutputDynamicsFit& fit, const std::vector<FilterPole>& poles, double rate,
                   const json& fit_test) {
  json scores = json::array(), pole_list = json::array();
  for (const auto& s : fit.scores) scores.push_back({{"order", s.order}, {"cv_fit", s.cv_fit}});
  for (const auto& p : poles) pole_list.push_back(pole_json(p));
  FilterPole dominant;
  const bool has_dominant = dominant_pole(poles, &dominant);
  return {{"model",
           {{"structure", "friction_gap -> B(q)/A(q)"},
            {"order", fit.filter.order()},
            {"a", fit.filter.a},
            {"b", fit.filter.b},
            {"dc_gain", fit.filter.dc_gain()},
            {"sample_rate_hz", rate},
            {"poles", pole_list},
            {"dominant_pole", has_dominant ? pole_json(dominant) : json(nullptr)}}},
          {"order_selection", {{"method", "leave one training file out"}, {"scores", scores}}},
          {"fit_train", fit.fit_train},
          {"fit_test", fit_test}};
}

void print_dynamics(const OutputDynamicsFit& fit, const std::vector<FilterPole>& poles) {
  fmt::print("Dynamics after the extended operator, B(q)/A(q) of order {} (orders by leave-one-training-file-out "
             "fit:",
             fit.filter.order());
  for (const auto& s : fit.scores) fmt::print(" {}: {:.1f} %", s.order, s.cv_fit);
  fmt::print("): static gain {:.3f}, training fit {:.1f} %\n  poles:", fit.filter.dc_gain(), fit.fit_train);
  for (const auto& p : poles) {
    fmt::print(" {:.5f}{:+.5f}i ({:.2f} Hz, zeta {:.3f})", p.z.real(), p.z.imag(), p.natural_hz, p.zeta);
  }
  fmt::print("\n\n");
}

json summary_json(const TestResults& r) {
  json out = json::object();
  for (const auto& [file, fit] : r.fit_nominal.items()) {
    out[file] = {{"nominal", fit}, {"extended", r.fit_extended[file]}, {"extended_dynamics", r.fit_dynamics[file]}};
  }
  return out;
}

// The figure's last panel: the nominal borders (200 points each) and the friction-gap curve G.
report::plot::Panel fitted_models_panel(const NominalFit& nominal, const ExtendedFit& extended) {
  std::vector<double> e_axis, g_axis;
  for (const auto& [e, g] : extended.curve) {
    e_axis.push_back(e);
    g_axis.push_back(g);
  }
  report::plot::Panel panel{"fitted models", "v (borders) or e = v - z (G)", "force u",
                            {{"nominal C_a", {}, {}}, {"nominal C_d", {}, {}}, {"friction_gap G(e)", e_axis, g_axis}}};
  for (std::size_t k = 0; k < 2; ++k) {
    const Border& b = k == 0 ? nominal.ascending : nominal.descending;
    for (int i = 0; i < 200; ++i) {
      const double v = b.lo() + (b.hi() - b.lo()) * i / 199.0;
      panel.series[k].x.push_back(v);
      panel.series[k].y.push_back(b(v));
    }
  }
  return panel;
}

// [min(0, min v), max(0, max v)] over the training files.
std::pair<double, double> training_range(const std::vector<DamperRecord>& train) {
  double v_lo = 0, v_hi = 0;
  for (const auto& rec : train) {
    v_lo = std::min(v_lo, *std::min_element(rec.v.begin(), rec.v.end()));
    v_hi = std::max(v_hi, *std::max_element(rec.v.begin(), rec.v.end()));
  }
  return {v_lo, v_hi};
}

json options_json(const OperatorFitArgs& args) {
  return {{"decimate", args.decimate}, {"points", args.points}, {"deadband", args.deadband},
          {"reversal_window", args.reversal_window}, {"engagement_window", args.engagement_window},
          {"parallel_stiffness", !args.no_stiffness}};
}

json nominal_json(const NominalFit& nominal, int points, const json& fit_test) {
  return {{"operator", nominal.chosen},
          {"fit_train", {{"switch", nominal.fit_train_switch}, {"backlash", nominal.fit_train_backlash}}},
          {"ascending", border_json(nominal.ascending, points)},
          {"descending", border_json(nominal.descending, points)},
          {"fit_test", fit_test}};
}

json extended_json(const ExtendedFit& extended, const HysteresisOperator& extended_op, const json& fit_test) {
  return {{"model",
           {{"operator", extended_op.name()},
            {"half_width", extended.half_width},
            {"stiffness", extended.stiffness},
            {"curve", table_json(extended.curve)},
            {"train_rms_by_half_width", table_json(extended.train_error_by_width)}}},
          {"fit_train", extended.fit_train},
          {"fit_test", fit_test}};
}

// Writes the figure, then the JSON; if the JSON cannot be written the figure is removed again.
void write_outputs(const OperatorFitArgs& args, const report::plot::Figure& figure, const json& document) {
  if (!args.plot_out.empty()) report::plot::write_png(figure, args.plot_out, args.gnuplot);
  if (args.json_out.empty()) return;
  try {
    write_json_file(args.json_out, document);
  } catch (...) {
    if (!args.plot_out.empty()) std::filesystem::remove(args.plot_out);
    throw;
  }
}

}  // namespace

int run_operator_fit(const OperatorFitArgs& args) {
  // Nothing half-written: every destination is checked before any work, and written only at the end.
  if (!args.json_out.empty()) check_can_write(args.json_out);
  if (!args.plot_out.empty()) check_can_write(args.plot_out);
  const std::vector<DamperRecord> train = load(args.train, args.decimate);
  const std::vector<DamperRecord> test = load(args.test, args.decimate);
  OperatorFitOptions fit_options;
  fit_options.points = args.points;
  fit_options.deadband = args.deadband;
  fit_options.parallel_stiffness = !args.no_stiffness;
  LoopPhaseOptions phase_options;
  phase_options.deadband = args.deadband;
  phase_options.reversal_window = args.reversal_window;
  phase_options.engagement_window = args.engagement_window;

  const NominalFit nominal = fit_nominal(train, fit_options);
  const auto nominal_op = nominal.make();
  fmt::print("Nominal operators, borders = per-bin medians on {} points ({} training files): training fit switch "
             "{:.1f} %, backlash {:.1f} % -> {}\n",
             args.points, train.size(), nominal.fit_train_switch, nominal.fit_train_backlash, nominal.chosen);
  const ExtendedFit extended = fit_extended(train, fit_options);
  const auto extended_op = extended.make();
  fmt::print("Extended operator friction_gap: play half-width r = {:.3f}, parallel stiffness k = {:.4f}, G on {} "
             "points: training fit {:.1f} %\n\n",
             extended.half_width, extended.stiffness, extended.curve.size(), extended.fit_train);

  const OutputDynamicsFit dynamics = fit_dynamics(train, *extended_op);
  const double rate = sampling_rate(train);
  const std::vector<FilterPole> poles = filter_poles(dynamics.filter, rate);
  print_dynamics(dynamics, poles);

  report::plot::Figure figure;
  figure.title = fmt::format("lashid operator-fit: measured vs {} (nominal) vs friction_gap (extended) vs "
                             "friction_gap + B/A", nominal.chosen);
  const TestResults results =
      evaluate_test_files(test, nominal, *nominal_op, *extended_op, dynamics.filter, rate, phase_options, figure);
  const auto [v_lo, v_hi] = training_range(train);
  std::vector<DamperCause> causes = damper_causes(results.nominal, results.extended, extended, v_hi - v_lo);
  const std::string dynamics_words = output_dynamics_in_words(poles, dynamics.filter.order(), results.errors);
  auto ringing = dynamics_after_friction_element(poles, dynamics.filter.order(), results.errors);
  const bool dynamics_named = ringing.has_value();
  if (ringing) causes.push_back(std::move(*ringing));
  print_causes(causes);
  if (!dynamics_named) {
    fmt::print("  - not named: dynamics_after_friction_element, too little gain (< {:.0f} % of the squared error): "
               "{}\n",
               100 * DamperCauseOptions{}.dynamics_error_reduction, dynamics_words);
  }
  figure.panels.push_back(fitted_models_panel(nominal, extended));

  const json identification = run_identification(*extended_op, v_lo, v_hi);
  const json document = {{"train", args.train},
                         {"options", options_json(args)},
                         {"nominal", nominal_json(nominal, args.points, results.fit_nominal)},
                         {"extended", extended_json(extended, *extended_op, results.fit_extended)},
                         {"dynamics", dynamics_json(dynamics, poles, rate, results.fit_dynamics)},
                         {"dynamics_in_words", {{"named_as_cause", dynamics_named}, {"text", dynamics_words}}},
                         {"fit_test", summary_json(results)},
                         {"cause", causes_json(causes)},
                         {"loop_analysis", results.loops},
                         {"identification", identification}};
  write_outputs(args, figure, document);
  return 0;
}

}  // namespace lashid::app
