// `lashid operator-fit`: the paper's operators and the friction-gap extension against measured damper data
// (docs/friction-damper.md).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <system_error>
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
#include "lashid/report/json.hpp"
#include "lashid/report/plot.hpp"
#include "lashid/report/report.hpp"
#include "lashid/sim/scenario.hpp"
#include "operator_fit_evaluation.hpp"
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

// A test file that is also a training file would be scored in-sample and reported as a test fit.
void check_held_out(const std::vector<std::string>& train, const std::vector<std::string>& test) {
  for (const auto& t : test) {
    for (const auto& f : train) {
      std::error_code error;
      if (t == f || std::filesystem::equivalent(t, f, error)) {
        throw std::invalid_argument(fmt::format("--test {} is also a --train file ({}): a test file must not be "
                                                "trained on, or its fit is in-sample",
                                                t, f));
      }
    }
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

// Sampling rate of the (possibly decimated) records: samples per second over the first training file's span. The
// discrete filter after the operator and the frequencies reported hold at one rate: every file must have it (within
// 1 %), or a test file at half the rate would be filtered at the wrong frequencies without a word.
double sampling_rate(const std::vector<DamperRecord>& train, const std::vector<DamperRecord>& test) {
  const auto rate_of = [](const DamperRecord& r) {
    const double rate = static_cast<double>(r.t.size() - 1) / (r.t.back() - r.t.front());
    if (!std::isfinite(rate) || !(rate > 0)) {
      throw DataError(r.source, fmt::format("{} samples in {:g} s: the sampling rate ({:g} per s) is not finite",
                                            r.t.size(), r.t.back() - r.t.front(), rate));
    }
    return rate;
  };
  const double rate = rate_of(train.front());
  for (const std::vector<DamperRecord>* files : {&train, &test}) {
    for (const DamperRecord& r : *files) {
      const double own = rate_of(r);
      if (std::fabs(own - rate) > 0.01 * rate) {
        throw DataError(r.source, fmt::format("sampled at {:.4g} per s, the first training file ({}) at {:.4g}: the "
                                              "filter after the operator needs one rate for every file",
                                              own, train.front().source, rate));
      }
    }
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
  if (!args.plot_out.empty()) report::plot::check_can_plot(args.plot_out, args.gnuplot);
  check_held_out(args.train, args.test);
  const std::vector<DamperRecord> train = load(args.train, args.decimate);
  const std::vector<DamperRecord> test = load(args.test, args.decimate);
  const double rate = sampling_rate(train, test);  // before any fit: files at another rate are refused first
  OperatorFitOptions fit_options;
  fit_options.points = args.points;
  fit_options.deadband = args.deadband;
  fit_options.parallel_stiffness = !args.no_stiffness;
  LoopPhaseOptions phase_options;
  phase_options.deadband = args.deadband;
  phase_options.reversal_window = args.reversal_window;
  phase_options.engagement_window = args.engagement_window;

  Tensions tensions = resolve_tensions(args, train, test);  // before any fit: a missing tension is an input error

  // The fits' own errors name their function and rule; said here in terms of the files and options given.
  const auto on_training_files = [&](auto fit) {
    try {
      return fit();
    } catch (const std::invalid_argument& e) {
      std::size_t samples = 0;
      for (const auto& r : train) samples += r.v.size();
      throw std::invalid_argument(fmt::format("cannot fit the operators to the {} --train file(s) ({} samples after "
                                              "--decimate {}, --points {}): {}",
                                              train.size(), samples, args.decimate, args.points, e.what()));
    }
  };
  const NominalFit nominal = on_training_files([&] { return fit_nominal(train, fit_options); });
  const auto nominal_op = nominal.make();
  fmt::print("Nominal operators, borders = per-bin medians on {} points ({} training files): training fit switch "
             "{:.1f} %, backlash {:.1f} % -> {}\n",
             args.points, train.size(), nominal.fit_train_switch, nominal.fit_train_backlash, nominal.chosen);
  const ExtendedFit extended = on_training_files([&] { return fit_extended(train, fit_options); });
  const auto extended_op = extended.make();
  fmt::print("Extended operator friction_gap (tension-blind): play half-width r = {:.3f}, parallel stiffness k = "
             "{:.4f}, G on {} points: training fit {:.1f} %\n",
             extended.half_width, extended.stiffness, extended.curve.size(), extended.fit_train);
  if (tensions.train.empty()) {
    fmt::print("No operator per band tension: {}\n\n", tensions.off_reason);
  } else {
    tensions.fit = on_training_files([&] { return fit_extended_by_tension(train, tensions.train, fit_options); });
    print_tension(*tensions.fit);
  }

  const OutputDynamicsFit dynamics = fit_dynamics(train, *extended_op, tensions);
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
