// `lashid scenarios` and `lashid simulate`: the built-in plants and plant files, and recordings of them.
#include <array>
#include <cmath>
#include <cstddef>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "commands.hpp"
#include "lashid/hil/config_design.hpp"
#include "lashid/io/data_error.hpp"
#include "lashid/io/files.hpp"
#include "lashid/io/plant_file.hpp"
#include "lashid/io/stop_signals.hpp"
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

// A recording streamed to its file (RecordingCsvStream: a temporary beside the target, renamed onto it at the end),
// so that memory does not grow with the design's lengths: `lashid design` takes a val_length of 2^31 - 1, which held
// in memory took about 44 bytes a sample (94 GB). Samples are counted per phase to name one that is not finite.
class StreamedRecording {
 public:
  StreamedRecording(const std::string& path, const std::vector<std::string>& comments) : out_(path, comments) {}
  // A plant whose values make its output overflow (a drift of 1e308 per sample, a huge gain) is the plant's fault,
  // not the output file's: said naming `culprit`, and the temporary file is removed (nothing written).
  void append(Phase phase, double v, double y, const std::string& culprit) {
    throw_if_stopped("simulate");  // the temporary file is removed on the way out (a stop signal: StopSignals)
    std::size_t& t = count_[phase_index(phase)];
    if (!std::isfinite(y)) {
      throw DataError(culprit, fmt::format("the plant's output is not finite at phase {} t = {} (y = {}): its "
                                           "values overflow the simulation (a gain, drift or noise too large, "
                                           "or A unstable); nothing written",
                                           to_string(phase), t, y));
    }
    out_.append(phase, v, y);
    ++t;
  }
  std::size_t rows() const { return out_.rows(); }
  void finish() { out_.finish(); }

 private:
  RecordingCsvStream out_;
  std::array<std::size_t, kPhaseCount> count_{};
};

// `simulate --plant PLANT --config CFG`: the device's run of the config's design on the plant, without firmware.
int run_simulate_plant(const SimulateArgs& args) {
  const PlantSpec spec = read_plant_json(args.plant);
  note_ignored_keys(spec, args.plant);
  const ExperimentConfig config = read_config_json(args.config);
  // The design the firmware would run for this config file: its lengths or their documented defaults.
  const fw::RunDesign design = to_run_design(config, args.config);
  check_plant_covers(spec, config.v_min, config.v_max, args.plant);  // before the output file is created
  const std::vector<std::string> comments{
      fmt::format("lashid simulate --plant {} --config {} --seed {}", args.plant, args.config, args.seed),
      plant_summary(spec),
      fmt::format("L = {}, N_d = {}, N_a = {}; val: {} samples of the firmware's validation excitation, seed {}",
                  design.step_length, design.pulse_length_d, design.pulse_length_a, design.val_length,
                  design.val_seed)};
  const StopSignals stop_signals;  // SIGINT and the like end the run through the removal of the temporary file
  StreamedRecording out(args.data_out, comments);
  stream_file_plant(spec, args.plant, config, design, args.seed,
                    [&](Phase phase, double v, double y) { out.append(phase, v, y, args.plant); });
  out.finish();
  fmt::print("wrote {} ({} samples)\n", args.data_out, out.rows());
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
  std::vector<std::string> comments{
      fmt::format("lashid simulate --scenario {} --seed {}", scenario.name, args.seed),
      scenario.description,
      fmt::format("noise variance {}, input lag lambda {}", scenario.noise_variance, args.input_lag)};
  // Nothing half-written: both destinations are checked before either is written, and if the recording still
  // fails (e.g. a full disk), the config just written is removed again.
  // A config that existed before is put back as it was (not deleted: it may be the user's only copy).
  check_can_write(args.data_out);
  if (!args.config_out.empty()) check_can_write(args.config_out);
  const StopSignals stop_signals;  // SIGINT and the like end the run through the cleanup below
  std::optional<std::string> previous_config;
  if (!args.config_out.empty()) {
    if (std::filesystem::is_regular_file(args.config_out)) previous_config = read_file_text(args.config_out);
    ExperimentConfig config = config_with_lengths(scenario);
    if (args.input_lag != 0) config.truth.reset();  // the truth of the nominal plant no longer applies
    write_json_file(args.config_out, to_json(config));
  }
  std::size_t rows = 0;
  try {
    StreamedRecording out(args.data_out, comments);
    stream_simulation(scenario, options,
                      [&](Phase phase, double v, double y) { out.append(phase, v, y, "--scenario " + scenario.name); });
    out.finish();
    rows = out.rows();
  } catch (...) {
    if (previous_config) {
      write_file_atomically(args.config_out, *previous_config);
    } else if (!args.config_out.empty()) {
      std::filesystem::remove(args.config_out);
    }
    throw;
  }
  fmt::print("wrote {} ({} samples){}\n", args.data_out, rows,
             args.config_out.empty() ? "" : fmt::format(" and {}", args.config_out));
  return 0;
}

}  // namespace lashid::app
