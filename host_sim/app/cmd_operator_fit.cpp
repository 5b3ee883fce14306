// `lashid operator-fit`: the paper's operators and the friction-gap extension against measured damper data
// (docs/friction-damper.md).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "lashid/identify/identify.hpp"
#include "lashid/io/config.hpp"
#include "lashid/io/data_error.hpp"
#include "lashid/io/files.hpp"
#include "lashid/operator_fit/band_tension.hpp"
#include "lashid/operator_fit/damper_causes.hpp"
#include "lashid/operator_fit/operator_fit.hpp"
#include "lashid/operator_fit/output_dynamics.hpp"
#include "lashid/operator_fit/test_profiles.hpp"
#include "lashid/report/json.hpp"
#include "lashid/report/plot.hpp"
#include "lashid/report/report.hpp"
#include "lashid/sim/scenario.hpp"
#include "operator_fit_report.hpp"

namespace lashid::app {

using namespace lashid::sim;
using nlohmann::json;

namespace {

std::vector<DamperRecord> load(const std::vector<std::string>& files, int factor) {
  std::vector<DamperRecord> out;
  for (const auto& f : files) out.push_back(decimate(read_damper_csv(f), factor));
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

// The band tension of every file, and the operator per tension when the training files span two tensions or more.
struct Tensions {
  std::vector<double> train;  // lb, one per training file (empty when the tension model is off)
  std::vector<double> test;   // lb, one per test file (same)
  std::optional<TensionFrictionFit> fit;
  std::string off_reason;     // why the tension model is off
};

// The tension of every file from --tension FILE=LB or the file name (tension_from_file_name). Off when no training
// file has one or all have the same; then test files need none. On: every file needs one, or a clear error.
Tensions resolve_tensions(const OperatorFitArgs& args, const std::vector<DamperRecord>& train,
                          const std::vector<DamperRecord>& test) {
  std::vector<TensionOverride> overrides;
  for (const auto& text : args.tension) {
    overrides.push_back(parse_tension_override(text));
    const auto names = [&](const std::vector<DamperRecord>& records) {
      return std::any_of(records.begin(), records.end(), [&](const DamperRecord& r) {
        return r.source == overrides.back().file ||
               std::filesystem::path(r.source).filename().string() == overrides.back().file;
      });
    };
    if (!names(train) && !names(test)) {
      throw std::invalid_argument(fmt::format("--tension '{}': no --train or --test file is named '{}'", text,
                                              overrides.back().file));
    }
  }
  Tensions out;
  std::vector<std::optional<double>> train_lb;
  for (const auto& r : train) train_lb.push_back(file_tension(r.source, overrides));
  const auto unknown = std::find(train_lb.begin(), train_lb.end(), std::nullopt);
  if (unknown == train_lb.end() || std::all_of(train_lb.begin(), train_lb.end(), [](auto t) { return !t; })) {
    std::vector<double> known;
    for (const auto& t : train_lb) {
      if (t) known.push_back(*t);
    }
    if (known.empty()) {
      out.off_reason = "no training file has a band tension (no '<T>lbtension' in its name, no --tension)";
      return out;
    }
    if (std::all_of(known.begin(), known.end(), [&](double t) { return t == known.front(); })) {
      out.off_reason = fmt::format("all training files are at {:g} lb", known.front());
      return out;
    }
    out.train = known;
  }
  const auto need = [](const DamperRecord& r, const std::optional<double>& t) {
    if (!t) {
      throw std::invalid_argument(fmt::format(
          "{}: band tension unknown: its name has no '<T>lbtension' and no --tension {}=LB was given (the training "
          "files span two band tensions, so every file needs one)",
          r.source, std::filesystem::path(r.source).filename().string()));
    }
    return *t;
  };
  if (out.train.empty()) need(train[static_cast<std::size_t>(unknown - train_lb.begin())], std::nullopt);
  for (const auto& r : test) out.test.push_back(need(r, file_tension(r.source, overrides)));
  return out;
}

// What the models do on the test files, one entry per file in the order of the files.
struct TestResults {
  json fit_nominal = json::object();   // file -> fit (%)
  json fit_extended = json::object();  // file -> fit (%)
  json fit_tension = json::object();   // file -> fit (%) of the operator per band tension (when on)
  json fit_dynamics = json::object();  // file -> fit (%) of the final operator followed by B/A
  json loops = json::object();         // file -> the loop analyses
  json profiles = json::object();      // file -> the final model's fit profiles over the record's unknowns
  std::vector<LoopAnalysis> nominal;
  std::vector<LoopAnalysis> final_operator;  // the tension model when on, else the tension-blind extended one
  TestErrors dynamics_gain;  // squared errors of the final operator without and with the dynamics
  TestErrors tension_gain;   // squared errors of the tension-blind and the tension model
  json oscillation_words = nullptr;  // the file whose final-model error is most fast oscillation, in words
};

double squared_error(const DamperRecord& rec, const std::vector<double>& u_sim) {
  double sum = 0;
  for (std::size_t t = 0; t < rec.u.size(); ++t) sum += (rec.u[t] - u_sim[t]) * (rec.u[t] - u_sim[t]);
  return sum;
}

// Simulates the models on every test file, prints their fits and loop analyses, and adds one panel per file.
TestResults evaluate_test_files(const std::vector<DamperRecord>& test, const NominalFit& nominal,
                                const HysteresisOperator& nominal_op, const FrictionGapOperator& extended_op,
                                const Tensions& tensions, const OutputFilter& dynamics, double rate,
                                const LoopPhaseOptions& phase_options, report::plot::Figure& figure) {
  TestResults out;
  const double files = static_cast<double>(test.size());
  for (std::size_t i = 0; i < test.size(); ++i) {
    const DamperRecord& rec = test[i];
    const auto u_nom = simulate_operator(nominal_op, rec.v, rec.u.front());
    const auto u_ext = simulate_operator(extended_op, rec.v, rec.u.front());
    // The final operator: per band tension at the file's own tension when on, else the tension-blind one.
    const auto at_tension = tensions.fit ? tensions.fit->make(tensions.test[i]) : nullptr;
    const FrictionGapOperator& final_op = at_tension ? *at_tension : extended_op;
    const auto u_fin = at_tension ? simulate_operator(final_op, rec.v, rec.u.front()) : u_ext;
    const auto u_dyn = dynamics.apply(u_fin, rec.u.front());
    const double f_nom = fit_to_record(rec, u_nom), f_ext = fit_to_record(rec, u_ext);
    const double f_fin = fit_to_record(rec, u_fin), f_dyn = fit_to_record(rec, u_dyn);
    out.fit_nominal[rec.source] = f_nom;
    out.fit_extended[rec.source] = f_ext;
    if (tensions.fit) out.fit_tension[rec.source] = f_fin;
    out.fit_dynamics[rec.source] = f_dyn;
    out.tension_gain.extended += squared_error(rec, u_ext);
    out.tension_gain.with_dynamics += squared_error(rec, u_fin);
    out.tension_gain.mean_fit_extended += f_ext / files;
    out.tension_gain.mean_fit_dynamics += f_fin / files;
    out.dynamics_gain.extended += squared_error(rec, u_fin);
    out.dynamics_gain.with_dynamics += squared_error(rec, u_dyn);
    out.dynamics_gain.mean_fit_extended += f_fin / files;
    out.dynamics_gain.mean_fit_dynamics += f_dyn / files;
    const std::string tension_text =
        tensions.fit ? fmt::format(", extended at {:g} lb{} {:.1f} %", tensions.test[i],
                                   tensions.fit->extrapolates(tensions.test[i]) ? " (extrapolated)" : "", f_fin)
                     : "";
    fmt::print("{}: {} samples, test fit nominal ({}) {:.1f} %, extended {:.1f} %{}, {} + dynamics {:.1f} %\n",
               rec.source, rec.v.size(), nominal.chosen, f_nom, f_ext, tension_text,
               tensions.fit ? "that" : "extended", f_dyn);
    const LoopAnalysis a_nom = analyse_loop(rec, u_nom, phase_options);
    const LoopAnalysis a_ext = analyse_loop(rec, u_ext, phase_options);
    const LoopAnalysis a_fin = analyse_loop(rec, u_fin, phase_options);
    const LoopAnalysis a_dyn = analyse_loop(rec, u_dyn, phase_options);
    print_analysis("nominal", a_nom, rec.v.size(), phase_options);
    print_analysis("extended", a_ext, rec.v.size(), phase_options);
    if (tensions.fit) print_analysis("extended per band tension", a_fin, rec.v.size(), phase_options);
    print_analysis(tensions.fit ? "extended per band tension + dynamics" : "extended + dynamics", a_dyn,
                   rec.v.size(), phase_options);
    // What the final operator still gets wrong: how much of its error is fast oscillation (chatter or ringing).
    const ErrorOscillation osc = error_oscillation(rec.u, u_fin, rate);
    // If that fast part stayed and everything else were right: ||e_fast|| = sqrt(share) ||e||, so the fit would be
    // 100 - sqrt(share) (100 - fit). A ceiling for any model that cannot predict the oscillation's phase.
    const double ceiling = 100 - std::sqrt(osc.fast_share) * (100 - f_fin);
    fmt::print("  {} model's error: {:.0f} % of its energy changes faster than about 10 Hz (the error minus its "
               "100 ms moving mean), with the largest amplitude, {:.3f}, at {:.0f} Hz; a model that still misses "
               "that fast part fits at most {:.1f} %\n",
               tensions.fit ? "Tension" : "Extended", 100 * osc.fast_share, osc.peak_amplitude, osc.peak_hz,
               ceiling);
    // Where that oscillation comes from: the displacement's cross-spectrum with the error at its peak.
    const DisplacementEcho echo = displacement_echo(rec.v, rec.u, u_fin, rate, osc.peak_hz);
    const std::string echo_words = displacement_echo_words(echo, a_fin.simulated_reversal_slope);
    fmt::print("  That fast part is {}\n", echo_words);
    if (out.oscillation_words.is_null() || osc.fast_share > out.oscillation_words["fast_share"].get<double>()) {
      out.oscillation_words = {{"file", rec.source}, {"fast_share", osc.fast_share}, {"peak_hz", osc.peak_hz},
                               {"fit_ceiling_without_it", ceiling}, {"text", echo_words}};
    }
    // Two things a test record does not tell, profiled for the final model (test_profiles.hpp): the slider's
    // initial position and the band tension (one training span beyond each end). Bounds, not scores.
    const FitProfile start = initial_offset_profile(final_op, dynamics, rec);
    print_profile(start, "slider's initial position", f_dyn);
    out.profiles[rec.source]["initial_offset"] = profile_json(start);
    if (tensions.fit) {
      const double lowest = tensions.fit->tensions.front().tension_lb, highest = tensions.fit->tensions.back().tension_lb;
      const double span = highest - lowest;
      const FitProfile tension = tension_profile(*tensions.fit, dynamics, rec, std::max(lowest - span, 0.0),
                                                 highest + span, 1.0);
      print_profile(tension, "band tension", f_dyn);
      out.profiles[rec.source]["tension"] = profile_json(tension);
    }
    out.nominal.push_back(a_nom);
    out.final_operator.push_back(a_fin);
    out.loops[rec.source] = {{"nominal", analysis_json(a_nom)},
                             {"extended", analysis_json(a_ext)},
                             {"extended_dynamics", analysis_json(a_dyn)},
                             {"extended_error_oscillation",
                              oscillation_json(tensions.fit ? "extended_tension" : "extended", osc, ceiling, echo,
                                               echo_words)}};
    if (tensions.fit) out.loops[rec.source]["extended_tension"] = analysis_json(a_fin);
    report::plot::Panel panel{std::filesystem::path(rec.source).filename().string(), "displacement v", "force u",
                              {{"measured", rec.v, rec.u},
                               {fmt::format("{} (nominal), fit {:.1f} %", nominal.chosen, f_nom), rec.v, u_nom},
                               {fmt::format("friction_gap, fit {:.1f} %", f_ext), rec.v, u_ext}}};
    if (tensions.fit) {
      panel.series.push_back({fmt::format("friction_gap at {:g} lb, fit {:.1f} %", tensions.test[i], f_fin), rec.v,
                              u_fin});
    }
    panel.series.push_back({fmt::format("{} + B/A, fit {:.1f} %", tensions.fit ? "that" : "friction_gap", f_dyn),
                            rec.v, u_dyn});
    figure.panels.push_back(std::move(panel));
  }
  return out;
}

// Sampling rate of the (possibly decimated) training records: samples per second over the first file's span.
double sampling_rate(const std::vector<DamperRecord>& train) {
  const DamperRecord& r = train.front();
  const double rate = static_cast<double>(r.t.size() - 1) / (r.t.back() - r.t.front());
  if (!std::isfinite(rate) || !(rate > 0)) {
    throw DataError(r.source, fmt::format("{} samples in {:g} s: the sampling rate ({:g} per s) is not finite",
                                          r.t.size(), r.t.back() - r.t.front(), rate));
  }
  return rate;
}

// The filter after the final operator (per band tension when on, each file at its own tension), from the training
// files only: input the operator's simulation, output the measured force.
OutputDynamicsFit fit_dynamics(const std::vector<DamperRecord>& train, const HysteresisOperator& extended_op,
                               const Tensions& tensions) {
  std::vector<FilterData> data;
  for (std::size_t i = 0; i < train.size(); ++i) {
    const auto op = tensions.fit ? tensions.fit->make(tensions.train[i]) : extended_op.clone();
    data.push_back({simulate_operator(*op, train[i].v, train[i].u.front()), train[i].u});
  }
  return fit_output_dynamics(data);
}

json summary_json(const TestResults& r) {
  json out = json::object();
  for (const auto& [file, fit] : r.fit_nominal.items()) {
    out[file] = {{"nominal", fit}, {"extended", r.fit_extended[file]}, {"extended_dynamics", r.fit_dynamics[file]}};
    if (r.fit_tension.contains(file)) out[file]["extended_tension"] = r.fit_tension[file];
  }
  return out;
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
          {"parallel_stiffness", !args.no_stiffness}, {"tension", args.tension}};
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

  Tensions tensions = resolve_tensions(args, train, test);  // before any fit: a missing tension is an input error

  const NominalFit nominal = fit_nominal(train, fit_options);
  const auto nominal_op = nominal.make();
  fmt::print("Nominal operators, borders = per-bin medians on {} points ({} training files): training fit switch "
             "{:.1f} %, backlash {:.1f} % -> {}\n",
             args.points, train.size(), nominal.fit_train_switch, nominal.fit_train_backlash, nominal.chosen);
  const ExtendedFit extended = fit_extended(train, fit_options);
  const auto extended_op = extended.make();
  fmt::print("Extended operator friction_gap (tension-blind): play half-width r = {:.3f}, parallel stiffness k = "
             "{:.4f}, G on {} points: training fit {:.1f} %\n",
             extended.half_width, extended.stiffness, extended.curve.size(), extended.fit_train);
  if (tensions.train.empty()) {
    fmt::print("No operator per band tension: {}\n\n", tensions.off_reason);
  } else {
    tensions.fit = fit_extended_by_tension(train, tensions.train, fit_options);
    print_tension(*tensions.fit);
  }

  const OutputDynamicsFit dynamics = fit_dynamics(train, *extended_op, tensions);
  const double rate = sampling_rate(train);
  const std::vector<FilterPole> poles = filter_poles(dynamics.filter, rate);
  print_dynamics(dynamics, poles);

  report::plot::Figure figure;
  figure.title = fmt::format("lashid operator-fit: measured vs {} (nominal) vs friction_gap (extended){} vs + B/A",
                             nominal.chosen, tensions.fit ? " vs friction_gap per band tension" : "");
  const TestResults results = evaluate_test_files(test, nominal, *nominal_op, *extended_op, tensions,
                                                  dynamics.filter, rate, phase_options, figure);
  const auto [v_lo, v_hi] = training_range(train);
  // The causes are judged on the final operator: per band tension, its parallel stiffness is the largest |k|.
  ExtendedFit judged = extended;
  if (tensions.fit) {
    judged.stiffness = 0;
    for (const auto& c : tensions.fit->tensions) {
      if (std::fabs(c.stiffness) >= std::fabs(judged.stiffness)) judged.stiffness = c.stiffness;
    }
  }
  std::vector<DamperCause> causes = damper_causes(results.nominal, results.final_operator, judged, v_hi - v_lo);
  json tension_words = nullptr;
  if (tensions.fit) {
    auto scaling = friction_level_scales_with_band_tension(*tensions.fit, results.tension_gain);
    tension_words = {{"named_as_cause", scaling.has_value()},
                     {"text", band_tension_in_words(*tensions.fit, results.tension_gain)}};
    if (scaling) causes.push_back(std::move(*scaling));
  }
  const std::string dynamics_words = output_dynamics_in_words(poles, dynamics.filter.order(), results.dynamics_gain);
  auto ringing = dynamics_after_friction_element(poles, dynamics.filter.order(), results.dynamics_gain);
  const bool dynamics_named = ringing.has_value();
  if (ringing) causes.push_back(std::move(*ringing));
  print_causes(causes);
  if (tensions.fit && !tension_words["named_as_cause"].get<bool>()) {
    fmt::print("  - not named: friction_level_scales_with_band_tension, too little gain (< {:.0f} % of the squared "
               "error): {}\n",
               100 * DamperCauseOptions{}.band_tension_error_reduction, tension_words["text"].get<std::string>());
  }
  if (!dynamics_named) {
    fmt::print("  - not named: dynamics_after_friction_element, too little gain (< {:.0f} % of the squared error): "
               "{}\n",
               100 * DamperCauseOptions{}.dynamics_error_reduction, dynamics_words);
  }
  print_oscillation_words(results.oscillation_words);
  figure.panels.push_back(fitted_models_panel(nominal, extended, tensions.fit ? &*tensions.fit : nullptr));

  // The actuator of DIS/AIS: the final operator, at the lowest training tension when it is per band tension.
  const auto actuator = tensions.fit ? tensions.fit->make(tensions.fit->tensions.front().tension_lb)
                                     : extended.make();
  const json identification = run_identification(*actuator, v_lo, v_hi);
  const std::string chain = tensions.fit ? "friction_gap per band tension -> B(q)/A(q)" : "friction_gap -> B(q)/A(q)";
  const json document = {
      {"train", args.train},
      {"options", options_json(args)},
      {"tension_lb", {{"train", tensions.train}, {"test", tensions.test}, {"off_reason", tensions.off_reason}}},
      {"nominal", nominal_json(nominal, args.points, results.fit_nominal)},
      {"extended", extended_json(extended, *extended_op, results.fit_extended)},
      {"extended_tension", tensions.fit ? tension_json(*tensions.fit, results.fit_tension) : json(nullptr)},
      {"tension_in_words", tension_words},
      {"dynamics", dynamics_json(dynamics, poles, rate, chain, results.fit_dynamics)},
      {"dynamics_in_words", {{"named_as_cause", dynamics_named}, {"text", dynamics_words}}},
      {"oscillation_in_words", results.oscillation_words},
      {"fit_test", summary_json(results)},
      {"cause", causes_json(causes)},
      {"loop_analysis", results.loops},
      {"test_profiles", results.profiles},
      {"identification", identification}};
  write_outputs(args, figure, document);
  return 0;
}

}  // namespace lashid::app
