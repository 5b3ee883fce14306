// Subcommands of the `lashid` tool. Each returns the process exit code; errors are thrown as exceptions and
// reported by main() with a non-zero exit.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "lashid/io/config.hpp"
#include "lashid/plant/effect.hpp"
#include "lashid/sim/hidden_effect.hpp"

namespace lashid::app {

struct SimulateArgs {
  std::string scenario;
  std::string plant;   // a plant file instead of a scenario (with `config`)
  std::string config;  // the experiment config a plant file is simulated with
  std::uint64_t seed = 1;
  double input_lag = 0;
  double noise_variance = -1;
  std::string data_out;
  std::string config_out;
};
int run_simulate(const SimulateArgs& args);

struct IdentifyArgs {
  std::string config;
  std::string data;
  std::string json_out;
  std::string scheme = "auto";  // dis, ais, both, or auto: those the data holds
  bool use_float = false;
};
int run_identify(const IdentifyArgs& args);

int run_scenarios();

struct ReproduceArgs {
  int runs = 1000;
  std::uint64_t seed = 1;
  std::string json_out;
};
int run_reproduce(const ReproduceArgs& args);

struct HilArgs {
  std::string firmware;
  std::vector<std::string> attach;  // LINK PLANT sockets
  std::string scenario;
  std::uint64_t seed = 1;
  std::string machine = "mps2-an386";
  std::string qemu = "qemu-system-arm";
  double timeout = 300;
  int corrupt_every = 0;
  double fault_rate = 0;
  std::uint64_t fault_seed = 1;
  std::string expect_estimates;  // an earlier run's --json: the estimates must equal its own exactly
  bool compare_host = false;
  double tolerance = 1e-3;
  double ticks_to_instructions = 0;
  bool icount = false;
  std::string json_out;
  std::string plant;   // a plant file played instead of the scenario's plant
  std::string record;  // the recording of the exchanged samples
  std::string config;  // the design sent, instead of the scenario's
  bool unchecked_design = false;  // send the config's design without the host's check (the firmware checks it)
  bool physical_plant = false;    // the board's own actuator and sensor: nothing played, the link only
};
int run_hil_command(const HilArgs& args);

struct QemuCommandArgs {
  std::string kernel;
  std::string machine = "mps2-an386";
  std::string qemu = "qemu-system-arm";
  std::vector<std::string> serials;
  bool icount = false;
};
int run_qemu_command(const QemuCommandArgs& args);

struct DiagnoseArgs {
  std::string config;
  std::string data;
  std::string json_out;
  std::string plot_out;
};
int run_diagnose(const DiagnoseArgs& args);

struct HiddenEffectArgs {
  std::string cause;  // one cause, or two joined by '+' (input_lag+sensor_drift)
  std::uint64_t seed = 1;
  std::string borders = "linear";  // "linear" or "curved" between the levels
  std::string data_out;
  std::string config_out;
};
int run_hidden_effect(const HiddenEffectArgs& args);
/// "input_lag+sensor_drift" -> {input_lag, sensor_drift}; throws std::invalid_argument naming an unknown cause.
std::vector<sim::Cause> parse_cause_list(std::string_view text);
/// "linear" or "curved"; throws std::invalid_argument otherwise.
sim::BorderShape parse_border_shape(std::string_view text);

struct DiagnoseSweepArgs {
  int seeds = 20;
  std::uint64_t first_seed = 1000;
  std::string borders = "linear";  // "linear" or "curved" between the levels
  bool pairs = false;              // the pairs of causes of issue 12 instead of one cause per recording
  std::vector<std::string> rows;   // only these rows (hidden causes, e.g. input_lag+sensor_drift); empty: all
  std::string json_out;
  bool verbose = false;
  bool oracle = false;  // also put the generator's plant on each true-structure fit's tables (sweep_oracle.hpp)
  bool oracle_regimes = false;  // the generator's plant as the only start of the lag search's fine backlash fits
};
int run_diagnose_sweep(const DiagnoseSweepArgs& args);

struct DesignArgs {
  std::string check;  // --check CFG.json: judge that file; empty: write a design to `out`
  int n = 0;
  int m = 0;
  double v_min = 0;
  double v_max = 0;
  std::string op;                    // "switch" or "backlash"
  std::optional<int> levels;         // K evenly spaced levels over [v_min, v_max]; nullopt: m + 1
  // Lengths as 64-bit so that any number typed reaches the config reader, whose error names the key and rule.
  std::int64_t step_length = sim::kDefaultStepLength;
  std::optional<std::int64_t> pulse_length;  // N of both pulse experiments; nullopt: sim::default_pulse_length
  std::int64_t val_length = sim::kDefaultValLength;
  std::int64_t val_seed = sim::kDefaultValSeed;
  std::string out;
};
int run_design(const DesignArgs& args);

struct OperatorFitArgs {
  std::vector<std::string> train;
  std::vector<std::string> test;
  std::string json_out;
  std::string plot_out;
  std::string gnuplot = "gnuplot";
  int decimate = 1;
  int points = 41;
  double deadband = 0.002;
  double reversal_window = 0.05;
  double engagement_window = 0.30;
  bool no_stiffness = false;
  std::vector<std::string> tension;  ///< FILE=LB: band tension of a file whose name has no <T>lbtension
};
int run_operator_fit(const OperatorFitArgs& args);

}  // namespace lashid::app
