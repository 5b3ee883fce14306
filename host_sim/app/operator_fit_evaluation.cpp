// The test side of `lashid operator-fit` (operator_fit_evaluation.hpp).
#include "operator_fit_evaluation.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <filesystem>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>

#include "lashid/operator_fit/band_tension.hpp"
#include "lashid/operator_fit/displacement_echo.hpp"
#include "lashid/operator_fit/test_profiles.hpp"
#include "operator_fit_report.hpp"

namespace lashid::app {

using namespace lashid::sim;
using nlohmann::json;

namespace {

double squared_error(const DamperRecord& rec, const std::vector<double>& u_sim) {
  double sum = 0;
  for (std::size_t t = 0; t < rec.u.size(); ++t) sum += (rec.u[t] - u_sim[t]) * (rec.u[t] - u_sim[t]);
  return sum;
}

}  // namespace

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

json summary_json(const TestResults& r) {
  json out = json::object();
  for (const auto& [file, fit] : r.fit_nominal.items()) {
    out[file] = {{"nominal", fit}, {"extended", r.fit_extended[file]}, {"extended_dynamics", r.fit_dynamics[file]}};
    if (r.fit_tension.contains(file)) out[file]["extended_tension"] = r.fit_tension[file];
  }
  return out;
}

}  // namespace lashid::app
