// `lashid diagnose` and `lashid hidden-effect` (a recording with hidden effects); `lashid diagnose-sweep` is in
// cmd_diagnose_sweep.cpp.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string_view>

#include <fmt/format.h>

#include "commands.hpp"
#include "lashid/diagnose/diagnosis.hpp"
#include "lashid/io/files.hpp"
#include "lashid/report/diagnose_plot.hpp"
#include "lashid/report/json.hpp"
#include "lashid/report/plot.hpp"
#include "lashid/sim/hidden_effect.hpp"

namespace lashid::app {

using namespace lashid::sim;

int run_diagnose(const DiagnoseArgs& args) {
  const ExperimentConfig config = read_config_json(args.config);
  // As identify reads it: a float32 device's levels (lashid hil --record) given back as the config's.
  const Recording rec = read_recording_for(config, args.data);
  for (const std::string& note : phase_length_notes(config, rec, args.data)) fmt::print(stderr, "lashid: note: {}\n", note);
  if (config.sensor_range) {
    // The DIS/AIS estimates leave these out as the device does (identify); the joint model cannot leave a sample
    // out of a simulation, so it fits them: said, so that a clipped sensor is not taken for a cause.
    const auto [lo, hi] = *config.sensor_range;
    std::size_t outside = 0;
    for (const Phase p : rec.order()) {
      for (const Sample& x : rec.phase(p)) outside += x.y < lo || x.y > hi ? 1U : 0U;
    }
    if (outside > 0) {
      fmt::print(stderr, "lashid: note: {}: {} samples lie outside the config's sensor_range [{:g}, {:g}]: the DIS/AIS "
                         "estimates leave them out, the joint model of the diagnosis fits them\n",
                 args.data, outside, lo, hi);
    }
  }
  if (!args.json_out.empty()) check_can_write(args.json_out);
  if (!args.plot_out.empty()) report::plot::check_can_plot(args.plot_out);
  const Diagnosis d = diagnose(config, rec, args.data);
  for (const std::string& line : d.findings) fmt::print("- {}\n", line);
  std::string names;
  for (Cause c : d.causes) {
    if (!names.empty()) names += '+';
    names += to_string(c);
  }
  // "cause" is the strongest; "parameters" those of every cause found (as in the JSON).
  // A fit below -999 % is a simulation that runs away: said in words, as in the findings, not as a 40-digit number.
  const auto fit = [](double f) { return f >= -999.0 ? fmt::format("{:.2f} %", f) : describe_fit(f); };
  fmt::print("causes: {}\ncause: {}\nparameters: {}\nfit_nominal: {}\nfit_extended: {}\n", names, to_string(d.cause),
             to_string(d.parameters), fit(d.fit_nominal), fit(d.fit_extended));
  if (!args.plot_out.empty()) report::plot_diagnosis(d, args.plot_out);
  if (!args.json_out.empty()) write_json_file(args.json_out, to_json(d));
  return 0;
}

std::vector<Cause> parse_cause_list(std::string_view text) {
  std::vector<Cause> causes;
  std::size_t begin = 0;
  while (begin <= text.size()) {
    const std::size_t end = std::min(text.find('+', begin), text.size());
    const std::string_view name = text.substr(begin, end - begin);
    const auto cause = parse_cause(name);
    if (!cause) {
      throw std::invalid_argument(fmt::format("--cause {}: unknown cause '{}' (none, input_lag, dead_time, "
                                              "sensor_drift, colored_noise, operator_type)",
                                              text, name));
    }
    causes.push_back(*cause);
    begin = end + 1;
  }
  return causes;
}

BorderShape parse_border_shape(std::string_view text) {
  if (text == "linear") return BorderShape::kLinearBetweenLevels;
  if (text == "curved") return BorderShape::kCurved;
  throw std::invalid_argument(fmt::format("unknown border shape '{}' (linear or curved)", text));
}

int run_hidden_effect(const HiddenEffectArgs& args) {
  HiddenEffectOptions options;
  options.borders = parse_border_shape(args.borders);
  const std::vector<Cause> causes = parse_cause_list(args.cause);
  HiddenEffectCase c;
  try {
    c = generate_hidden_effect_case(causes, args.seed, options);
  } catch (const std::invalid_argument& e) {
    // The generator's rules on the list (a repeat, none with another) said in terms of the option.
    std::string_view why = e.what();
    constexpr std::string_view kPrefix = "generate_hidden_effect_case: ";
    if (why.starts_with(kPrefix)) why.remove_prefix(kPrefix.size());
    throw std::invalid_argument(fmt::format("--cause {}: {}", args.cause, why));
  }
  check_can_write(args.data_out);
  check_can_write(args.config_out);
  // The config says what the recording holds, as simulate's does: its lengths (docs/data-format.md).
  ExperimentConfig config = c.config;
  const auto length = [&](Phase p) { return static_cast<int>(c.recording.phase(p).size()); };
  if (length(Phase::kStepD) == length(Phase::kStepA)) config.step_length = length(Phase::kStepD) - 1;
  config.pulse_length_d = length(Phase::kDis);
  config.pulse_length_a = length(Phase::kAis);
  config.val_length = length(Phase::kVal);
  write_json_file(args.config_out, to_json(config));
  try {
    write_recording_csv(args.data_out, c.recording,
                        {fmt::format("lashid hidden-effect --cause {} --seed {} --borders {} (the effect is not in "
                                     "the config)",
                                     args.cause, args.seed, args.borders)});
  } catch (...) {
    std::filesystem::remove(args.config_out);
    throw;
  }
  fmt::print("wrote {} and {} ({} samples; n = {}, m = {})\n", args.data_out, args.config_out, c.recording.size(),
             c.config.n, c.config.m);
  return 0;
}

}  // namespace lashid::app
