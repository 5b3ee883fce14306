// `lashid scenarios` and `lashid simulate`: the built-in plants and plant files, and recordings of them.
#include <cmath>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "commands.hpp"
#include "lashid/hil/config_design.hpp"
#include "lashid/io/data_error.hpp"
#include "lashid/io/files.hpp"
#include "lashid/io/plant_file.hpp"
#include "lashid/report/json.hpp"
#include "lashid/sim/file_plant.hpp"
#include "lashid/sim/scenario.hpp"
#include "plant_notes.hpp"

namespace lashid::app {

using namespace lashid::sim;

int run_scenarios() {
  for (const Scenario& s : builtin_scenarios()) fmt::print("{:<12} {}\n", s.name, s.description);
  return 0;
}

namespace {

// `simulate --plant PLANT --config CFG`: the device's run of the config's design on the plant, without firmware.
int run_simulate_plant(const SimulateArgs& args) {
  const PlantSpec spec = read_plant_json(args.plant);
  note_ignored_keys(spec, args.plant);
  const ExperimentConfig config = read_config_json(args.config);
  // The design the firmware would run for this config file: its lengths or their documented defaults.
  const fw::RunDesign design = to_run_design(config, args.config);
  const Recording rec = simulate_file_plant(spec, args.plant, config, design, args.seed);
  // A plant whose values make its output overflow (a drift of 1e308 per sample, a huge gain) is the plant file's
  // fault, not the output file's: said before anything is written.
  for (const Phase phase : rec.order()) {
    const auto samples = rec.phase(phase);
    for (std::size_t t = 0; t < samples.size(); ++t) {
      if (std::isfinite(samples[t].y)) continue;
      throw DataError(args.plant, fmt::format("the plant's output is not finite at phase {} t = {} (y = {}): its "
                                              "values overflow the simulation (a gain, drift or noise too large, "
                                              "or A unstable); nothing written",
                                              to_string(phase), t, samples[t].y));
    }
  }
  const std::vector<std::string> comments{
      fmt::format("lashid simulate --plant {} --config {} --seed {}", args.plant, args.config, args.seed),
      plant_summary(spec),
      fmt::format("L = {}, N_d = {}, N_a = {}; val: {} samples of the firmware's validation excitation, seed {}",
                  design.step_length, design.pulse_length_d, design.pulse_length_a, design.val_length,
                  design.val_seed)};
  write_recording_csv(args.data_out, rec, comments);
  fmt::print("wrote {} ({} samples)\n", args.data_out, rec.size());
  return 0;
}

}  // namespace

int run_simulate(const SimulateArgs& args) {
  if (!args.plant.empty()) return run_simulate_plant(args);
  Scenario scenario = find_scenario(args.scenario);
  if (args.noise_variance >= 0) scenario.noise_variance = args.noise_variance;
  SimulationOptions options;
  options.seed = args.seed;
  options.input_lag = args.input_lag;
  const Recording rec = simulate(scenario, options);
  std::vector<std::string> comments{
      fmt::format("lashid simulate --scenario {} --seed {}", scenario.name, args.seed),
      scenario.description,
      fmt::format("noise variance {}, input lag lambda {}", scenario.noise_variance, args.input_lag)};
  // Nothing half-written: both destinations are checked before either is written, and if the recording still
  // fails (e.g. a full disk), the config just written is removed again.
  // A config that existed before is put back as it was (not deleted: it may be the user's only copy).
  check_can_write(args.data_out);
  if (!args.config_out.empty()) check_can_write(args.config_out);
  std::optional<std::string> previous_config;
  if (!args.config_out.empty()) {
    if (std::filesystem::is_regular_file(args.config_out)) previous_config = read_file_text(args.config_out);
    ExperimentConfig config = config_with_lengths(scenario);
    if (args.input_lag != 0) config.truth.reset();  // the truth of the nominal plant no longer applies
    write_json_file(args.config_out, to_json(config));
  }
  try {
    write_recording_csv(args.data_out, rec, comments);
  } catch (...) {
    if (previous_config) {
      write_file_atomically(args.config_out, *previous_config);
    } else if (!args.config_out.empty()) {
      std::filesystem::remove(args.config_out);
    }
    throw;
  }
  fmt::print("wrote {} ({} samples){}\n", args.data_out, rec.size(),
             args.config_out.empty() ? "" : fmt::format(" and {}", args.config_out));
  return 0;
}

}  // namespace lashid::app
