// `lashid operator-fit`: the paper's operators and the friction-gap extension against measured damper data
// (docs/friction-damper.md).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "lashid/identify/identify.hpp"
#include "lashid/io/config.hpp"
#include "lashid/io/files.hpp"
#include "lashid/operator_fit/operator_fit.hpp"
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

// Causes supported by the nominal model's errors on the test files (aggregated), see docs/friction-damper.md.
json causes(const std::vector<LoopAnalysis>& nominal, const std::vector<LoopAnalysis>& extended,
           const ExtendedFit& ext, double v_span) {
  double reversal_share = 0, engagement_share = 0, measured_slope = 0, simulated_slope = 0, measured_gap = 0,
         simulated_gap = 0, plateau = 0, spread = 0;
  for (const auto& a : nominal) {
    spread = std::max(spread, a.measured_gap_centre_spread);
    reversal_share += a.phases[0].share_of_squared_error;
    engagement_share += a.phases[1].share_of_squared_error;
    measured_slope += a.measured_reversal_slope;
    simulated_slope += a.simulated_reversal_slope;
    measured_gap += a.measured_gap;
    simulated_gap += a.simulated_gap;
    plateau += a.plateau;
  }
  const double n = static_cast<double>(nominal.size());
  json out = json::array();
  if ((reversal_share + engagement_share) / n > 0.5) {
    out.push_back({{"name", "finite_stiffness_at_reversal"}, {"in_extended_model", true},
                   {"evidence", fmt::format("on average {:.0f} % (reversal) + {:.0f} % (engagement) of the nominal "
                                            "squared error follows a reversal; measured force changes at {:.1f} per "
                                            "unit of v just after reversals, the nominal simulation at {:.1f}",
                                            100 * reversal_share / n, 100 * engagement_share / n,
                                            measured_slope / n, simulated_slope / n)}});
  }
  if (measured_gap / n > 0.02 && spread > measured_gap / n) {
    out.push_back({{"name", "zero_force_gap_moving_with_reversal"}, {"in_extended_model", true},
                   {"evidence", fmt::format("the measured force stays below 10 % of the friction level for {:.3f} "
                                            "of travel per half-cycle (nominal simulation: {:.3f}), and the position of "
                                            "this gap spreads over {:.3f} across half-cycles: it follows the last "
                                            "reversal, which no border C(v) of v alone can represent",
                                            measured_gap / n, simulated_gap / n, spread)}});
  }
  if (std::fabs(ext.stiffness) * v_span > 0.05 * plateau / n) {
    out.push_back({{"name", "position_dependent_friction"}, {"in_extended_model", true},
                   {"evidence", fmt::format("the sliding force changes with displacement at {:.3f} per unit of v "
                                            "(fitted parallel stiffness), {:.0f} % of the friction level over the "
                                            "training range",
                                            ext.stiffness, 100 * std::fabs(ext.stiffness) * v_span / (plateau / n))}});
  }
  // Rate: the extended (rate-independent) model's sliding error at the fastest vs the slowest test file.
  const auto by_speed = [](const LoopAnalysis& a, const LoopAnalysis& b) { return a.peak_speed < b.peak_speed; };
  std::vector<LoopAnalysis> sorted;
  for (const auto& a : extended) {
    if (a.phases[2].samples > 0) sorted.push_back(a);
  }
  std::sort(sorted.begin(), sorted.end(), by_speed);
  if (sorted.size() >= 2 && sorted.back().phases[2].rms > 1.5 * sorted.front().phases[2].rms) {
    out.push_back({{"name", "rate_dependence"}, {"in_extended_model", false},
                   {"evidence", fmt::format("the extended model's RMS error while sliding is {:.3f} at a peak speed "
                                            "of {:.2f} per s and {:.3f} at {:.2f} per s (force oscillation on the "
                                            "plateau); the operators are rate-independent",
                                            sorted.back().phases[2].rms, sorted.back().peak_speed,
                                            sorted.front().phases[2].rms, sorted.front().peak_speed)}});
  }
  return out;
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

  json fit_nominal_json = json::object(), fit_extended_json = json::object(), loops = json::object();
  std::vector<LoopAnalysis> nominal_analyses, extended_analyses;
  report::plot::Figure figure;
  figure.title = fmt::format("lashid operator-fit: measured vs {} (nominal) vs friction_gap (extended)",
                             nominal.chosen);
  for (const auto& rec : test) {
    const auto u_nom = simulate_operator(*nominal_op, rec.v, rec.u.front());
    const auto u_ext = simulate_operator(*extended_op, rec.v, rec.u.front());
    const double f_nom = fit_percent(rec.u, u_nom), f_ext = fit_percent(rec.u, u_ext);
    fit_nominal_json[rec.source] = f_nom;
    fit_extended_json[rec.source] = f_ext;
    fmt::print("{}: {} samples, test fit nominal ({}) {:.1f} %, extended {:.1f} %\n", rec.source, rec.v.size(),
               nominal.chosen, f_nom, f_ext);
    const LoopAnalysis a_nom = analyse_loop(rec, u_nom, phase_options);
    const LoopAnalysis a_ext = analyse_loop(rec, u_ext, phase_options);
    print_analysis("nominal", a_nom, rec.v.size(), phase_options);
    print_analysis("extended", a_ext, rec.v.size(), phase_options);
    nominal_analyses.push_back(a_nom);
    extended_analyses.push_back(a_ext);
    loops[rec.source] = {{"nominal", analysis_json(a_nom)}, {"extended", analysis_json(a_ext)}};
    figure.panels.push_back({std::filesystem::path(rec.source).filename().string(), "displacement v", "force u",
                             {{"measured", rec.v, rec.u},
                              {fmt::format("{} (nominal), fit {:.1f} %", nominal.chosen, f_nom), rec.v, u_nom},
                              {fmt::format("friction_gap, fit {:.1f} %", f_ext), rec.v, u_ext}}});
  }
  double v_lo = 0, v_hi = 0;
  for (const auto& rec : train) {
    v_lo = std::min(v_lo, *std::min_element(rec.v.begin(), rec.v.end()));
    v_hi = std::max(v_hi, *std::max_element(rec.v.begin(), rec.v.end()));
  }
  const json cause = causes(nominal_analyses, extended_analyses, extended, v_hi - v_lo);
  fmt::print("\nCauses supported by the errors on the test files:\n");
  for (const auto& c : cause) {
    fmt::print("  - {} ({}): {}\n", c["name"].get<std::string>(),
               c["in_extended_model"].get<bool>() ? "in the extended model" : "not modelled",
               c["evidence"].get<std::string>());
  }
  std::vector<double> e_axis, g_axis;
  for (const auto& [e, g] : extended.curve) {
    e_axis.push_back(e);
    g_axis.push_back(g);
  }
  figure.panels.push_back({"fitted models", "v (borders) or e = v - z (G)", "force u",
                           {{"nominal C_a", {}, {}}, {"nominal C_d", {}, {}}, {"friction_gap G(e)", e_axis, g_axis}}});
  for (int k = 0; k < 2; ++k) {
    const Border& b = k == 0 ? nominal.ascending : nominal.descending;
    for (int i = 0; i < 200; ++i) {
      const double v = b.lo() + (b.hi() - b.lo()) * i / 199.0;
      figure.panels.back().series[static_cast<std::size_t>(k)].x.push_back(v);
      figure.panels.back().series[static_cast<std::size_t>(k)].y.push_back(b(v));
    }
  }

  json identification = run_identification(*extended_op, v_lo, v_hi);

  json out = {{"train", args.train},
              {"options",
               {{"decimate", args.decimate}, {"points", args.points}, {"deadband", args.deadband},
                {"reversal_window", args.reversal_window}, {"engagement_window", args.engagement_window},
                {"parallel_stiffness", !args.no_stiffness}}},
              {"nominal",
               {{"operator", nominal.chosen},
                {"fit_train", {{"switch", nominal.fit_train_switch}, {"backlash", nominal.fit_train_backlash}}},
                {"ascending", border_json(nominal.ascending, args.points)},
                {"descending", border_json(nominal.descending, args.points)},
                {"fit_test", fit_nominal_json}}},
              {"extended",
               {{"model",
                 {{"operator", extended_op->name()},
                  {"half_width", extended.half_width},
                  {"stiffness", extended.stiffness},
                  {"curve", table_json(extended.curve)},
                  {"train_rms_by_half_width", table_json(extended.train_error_by_width)}}},
                {"fit_train", extended.fit_train},
                {"fit_test", fit_extended_json}}},
              {"cause", cause},
              {"loop_analysis", loops},
              {"identification", identification}};
  if (!args.plot_out.empty()) report::plot::write_png(figure, args.plot_out, args.gnuplot);
  if (!args.json_out.empty()) {
    try {
      write_json_file(args.json_out, out);
    } catch (...) {
      if (!args.plot_out.empty()) std::filesystem::remove(args.plot_out);
      throw;
    }
  }
  return 0;
}

}  // namespace lashid::app
