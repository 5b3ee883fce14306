// lashid: identification of actuators with backlash or switch behaviour followed by linear dynamics (DIS/AIS).
#include <cstdio>
#include <exception>
#include <string>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "commands.hpp"

namespace {

// CLI11 converts "-1" to an unsigned seed by wrapping it around to 2^64 - 1; reject it instead.
const CLI::Validator kNonNegativeSeed(
    [](const std::string& value) { return value.starts_with('-') ? std::string("must not be negative") : std::string(); },
    "NONNEGATIVE");

}  // namespace

int main(int argc, char** argv) {
  using namespace lashid::app;
  CLI::App app{"lashid: DIS/AIS identification of Hammerstein-like systems with switch or backlash nonlinearities\n"
               "(Giri et al., nonparametric borders). See README.md and docs/."};
  app.require_subcommand(1);

  auto* scenarios = app.add_subcommand("scenarios", "List the built-in simulation scenarios");

  SimulateArgs sim;
  auto* simulate = app.add_subcommand("simulate", "Simulate a recording (step_d, dis, step_a, ais, val) of a scenario");
  simulate->add_option("--scenario", sim.scenario, "Scenario name (see `lashid scenarios`)")->required();
  simulate->add_option("--seed", sim.seed, "Seed of the noise and of the validation input")
      ->check(kNonNegativeSeed)
      ->capture_default_str();
  simulate->add_option("--input-lag", sim.input_lag,
                       "lambda of G = (1-lambda)/(1-lambda q^-1) before the operator (Section 3.5.3)")
      ->check(CLI::Range(0.0, 0.999))
      ->capture_default_str();
  simulate->add_option("--noise-variance", sim.noise_variance, "Override the scenario's noise variance")
      ->check(CLI::NonNegativeNumber);
  simulate->add_option("--out", sim.data_out, "Recording to write (CSV, docs/data-format.md)")->required();
  simulate->add_option("--config-out", sim.config_out, "Config to write (JSON, with the truth)");

  IdentifyArgs id;
  auto* identify = app.add_subcommand("identify", "Run DIS and/or AIS on a recording and print the estimates");
  identify->add_option("--config", id.config, "Experiment config (JSON)")->required()->check(CLI::ExistingFile);
  identify->add_option("--data", id.data, "Recording (CSV)")->required()->check(CLI::ExistingFile);
  identify->add_option("--json", id.json_out, "Write the estimates as JSON");
  identify->add_option("--scheme", id.scheme, "Which scheme(s): dis, ais or both (default: those the data holds)")
      ->check(CLI::IsMember({"dis", "ais", "both"}));
  identify->add_flag("--float", id.use_float, "Run the estimator in float32, as the firmware does");

  ReproduceArgs rep;
  auto* reproduce = app.add_subcommand("reproduce", "Reproduce the paper's examples, Table 3 and the consistency check");
  reproduce->add_option("--runs", rep.runs, "Monte Carlo repetitions (Section 3.5.2)")
      ->check(CLI::Range(10, 100000))
      ->capture_default_str();
  reproduce->add_option("--seed", rep.seed, "Seed of the single runs")
      ->check(kNonNegativeSeed)
      ->capture_default_str();
  reproduce->add_option("--json", rep.json_out, "Write all numbers as JSON");

  HilArgs hil;
  auto* hil_cmd = app.add_subcommand("hil", "Run the firmware in QEMU and play the actuator and plant over its UART");
  auto* fw_opt = hil_cmd->add_option("--firmware", hil.firmware, "Firmware ELF to start QEMU with (cross preset build)")
                    ->check(CLI::ExistingFile);
  auto* attach_opt = hil_cmd->add_option("--attach", hil.attach,
                                         "Attach to a running QEMU instead: its UART0 and UART1 Unix sockets "
                                         "(-serial unix:LINK,server=on,wait=off -serial unix:PLANT,server=on,wait=off)")
                         ->expected(2);
  fw_opt->excludes(attach_opt);
  hil_cmd->callback([&] {
    if (hil.firmware.empty() && hil.attach.empty()) throw CLI::RequiredError("--firmware or --attach");
  });
  hil_cmd->add_option("--scenario", hil.scenario, "Plant played by the host (must match the firmware's config)")
      ->required();
  hil_cmd->add_option("--seed", hil.seed, "Noise seed of the plant")->check(kNonNegativeSeed)->capture_default_str();
  hil_cmd->add_option("--machine", hil.machine, "QEMU machine: mps2-an386 (M4F), mps2-an500 (M7), mps2-an385 (M3)")
      ->capture_default_str();
  hil_cmd->add_option("--qemu", hil.qemu, "QEMU executable")->capture_default_str();
  hil_cmd->add_option("--timeout", hil.timeout, "Wall-clock limit in seconds")->check(CLI::PositiveNumber)
      ->capture_default_str();
  hil_cmd->add_option("--corrupt-every", hil.corrupt_every,
                      "Fault injection: damage every k-th measurement frame (the firmware must detect it)")
      ->check(CLI::NonNegativeNumber);
  hil_cmd->add_flag("--compare-host", hil.compare_host,
                    "Also run the same firmware on the in-process host board and require equal estimates");
  hil_cmd->add_option("--tolerance", hil.tolerance, "Relative tolerance of --compare-host")->capture_default_str();
  hil_cmd->add_option("--ticks-to-instructions", hil.ticks_to_instructions,
                      "Convert the board's cycle counts to instructions (QEMU -icount shift=0, SysTick at 25 MHz: 40)");
  hil_cmd->add_flag("--icount", hil.icount,
                    "Run QEMU with -icount shift=0 (deterministic cycle counts; much slower exchanges)");
  hil_cmd->add_option("--json", hil.json_out, "Write the results as JSON");

  QemuCommandArgs qemu;
  auto* qemu_cmd = app.add_subcommand(
      "qemu-command", "Print the qemu-system-arm command line for an image, one argument per line (cmake/Qemu.cmake)");
  qemu_cmd->add_option("--kernel", qemu.kernel, "Firmware ELF")->required();
  qemu_cmd->add_option("--machine", qemu.machine, "QEMU machine")->capture_default_str();
  qemu_cmd->add_option("--qemu", qemu.qemu, "QEMU executable")->capture_default_str();
  qemu_cmd->add_option("--serial", qemu.serials, "-serial backend of the next UART (UART0 first); repeatable");
  qemu_cmd->add_flag("--icount", qemu.icount, "Add -icount shift=0 (deterministic instruction counts)");

  DiagnoseArgs diag;
  auto* diagnose = app.add_subcommand(
      "diagnose", "Simulate the identified model on 'val', find what it gets wrong, name the cause, extend, refit");
  diagnose->add_option("--config", diag.config, "Experiment config (JSON)")->required()->check(CLI::ExistingFile);
  diagnose->add_option("--data", diag.data, "Recording with all five phases (CSV)")->required()->check(CLI::ExistingFile);
  diagnose->add_option("--json", diag.json_out, "Write cause, parameters, fits, evidence and both models as JSON");
  diagnose->add_option("--plot", diag.plot_out, "Write a PNG: val simulations, residual correlations with bands");

  HiddenEffectArgs hidden;
  auto* hidden_cmd = app.add_subcommand("hidden-effect", "Generate a random plant's recording with a hidden effect");
  hidden_cmd->add_option("--cause", hidden.cause, "none, input_lag, dead_time, sensor_drift, colored_noise, operator_type")
      ->required()
      ->check(CLI::IsMember({"none", "input_lag", "dead_time", "sensor_drift", "colored_noise", "operator_type"}));
  hidden_cmd->add_option("--seed", hidden.seed, "Seed of the plant, the effect's size and the noise")
      ->check(kNonNegativeSeed)
      ->capture_default_str();
  hidden_cmd->add_option("--out", hidden.data_out, "Recording to write (CSV)")->required();
  hidden_cmd->add_option("--config-out", hidden.config_out, "Config to write (JSON, without the effect)")->required();

  DiagnoseSweepArgs sweep;
  auto* sweep_cmd = app.add_subcommand("diagnose-sweep",
                                       "Diagnose many hidden-effect recordings: hit rate per cause, confusion matrix");
  sweep_cmd->add_option("--seeds", sweep.seeds, "Recordings per cause")->check(CLI::Range(1, 10000))
      ->capture_default_str();
  sweep_cmd->add_option("--first-seed", sweep.first_seed, "First seed")->check(kNonNegativeSeed)->capture_default_str();
  sweep_cmd->add_option("--json", sweep.json_out, "Write the matrix and every case as JSON");
  sweep_cmd->add_flag("--verbose", sweep.verbose, "Print every miss");
  OperatorFitArgs opfit;
  auto* opfit_cmd = app.add_subcommand(
      "operator-fit",
      "Fit switch/backlash and a friction-gap operator to measured force-displacement CSVs (t_s, x_in, F_kip), "
      "test them on other files, run DIS/AIS with the fit as actuator (docs/friction-damper.md)");
  opfit_cmd->add_option("--train", opfit.train, "Training files (CSV)")->required()->check(CLI::ExistingFile);
  opfit_cmd->add_option("--test", opfit.test, "Test files (CSV), never used for fitting")->required()
      ->check(CLI::ExistingFile);
  opfit_cmd->add_option("--json", opfit.json_out, "Write the fits, models, causes and analysis as JSON");
  opfit_cmd->add_option("--plot", opfit.plot_out, "Write the measured and simulated loops as PNG (needs gnuplot)");
  opfit_cmd->add_option("--gnuplot", opfit.gnuplot, "gnuplot executable")->capture_default_str();
  opfit_cmd->add_option("--decimate", opfit.decimate,
                        "Resampling: replace every K samples by their mean (1: the data as recorded)")
      ->check(CLI::Range(1, 1000))->capture_default_str();
  opfit_cmd->add_option("--points", opfit.points, "Nodes of each fitted table (borders, G)")
      ->check(CLI::Range(2, 10000))->capture_default_str();
  opfit_cmd->add_option("--deadband", opfit.deadband,
                        "Reversal detection: v must retreat this far from its extreme (units of v)")
      ->check(CLI::NonNegativeNumber)->capture_default_str();
  opfit_cmd->add_option("--reversal-window", opfit.reversal_window,
                        "Error analysis: 'reversal' = travel since the last reversal below this")
      ->check(CLI::PositiveNumber)->capture_default_str();
  opfit_cmd->add_option("--engagement-window", opfit.engagement_window,
                        "Error analysis: 'engagement' = travel below this (and above the reversal window)")
      ->check(CLI::PositiveNumber)->capture_default_str();
  opfit_cmd->add_flag("--no-stiffness", opfit.no_stiffness, "Extended model without the parallel stiffness k");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  try {
    if (*scenarios) return run_scenarios();
    if (*simulate) return run_simulate(sim);
    if (*identify) return run_identify(id);
    if (*reproduce) return run_reproduce(rep);
    if (*hil_cmd) return run_hil_command(hil);
    if (*qemu_cmd) return run_qemu_command(qemu);
    if (*diagnose) return run_diagnose(diag);
    if (*hidden_cmd) return run_hidden_effect(hidden);
    if (*sweep_cmd) return run_diagnose_sweep(sweep);
    if (*opfit_cmd) return run_operator_fit(opfit);
  } catch (const std::exception& e) {
    std::fflush(stdout);
    fmt::print(stderr, "lashid: error: {}\n", e.what());
    return 1;
  }
  return 0;
}
