// lashid: identification of actuators with backlash or switch behaviour followed by linear dynamics (DIS/AIS).
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <functional>
#include <limits>
#include <new>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "cli_checks.hpp"
#include "cli_options.hpp"
#include "commands.hpp"
#include "lashid/estimator/design.hpp"
#include "lashid/hil/hil.hpp"
#include "output_paths.hpp"

using namespace lashid::app;

namespace {

struct Arguments {
  SimulateArgs simulate;
  IdentifyArgs identify;
  ReproduceArgs reproduce;
  HilArgs hil;
  QemuCommandArgs qemu_command;
  DiagnoseArgs diagnose;
  HiddenEffectArgs hidden_effect;
  DiagnoseSweepArgs diagnose_sweep;
  OperatorFitArgs operator_fit;
  DesignArgs design;
};

CLI::App* add_simulate(CLI::App& app, SimulateArgs& args) {
  auto* cmd = app.add_subcommand("simulate", "Simulate a recording (step_d, dis, step_a, ais, val) of a scenario or "
                                             "of a plant file");
  auto* scenario = cmd->add_option("--scenario", args.scenario, "Scenario name (see `lashid scenarios`)");
  auto* plant = cmd->add_option("--plant", args.plant,
                                "Plant file (JSON, docs/data-format.md) instead of a scenario; needs --config")
                    ->check(CLI::ExistingFile);
  auto* config = cmd->add_option("--config", args.config,
                                 "Experiment config (JSON) whose design the plant file is run with, as the device "
                                 "would run it (val phase from the firmware's validation generator)")
                     ->check(CLI::ExistingFile);
  scenario->excludes(plant);
  plant->needs(config);
  config->needs(plant);
  cmd->callback([&args] {
    if (args.scenario.empty() && args.plant.empty()) throw CLI::RequiredError("--scenario or --plant");
  });
  cmd->add_option("--seed", args.seed, "Seed of the noise and, for a scenario, of the validation input (with --plant the config's "
                  "val_seed gives that input)")
      ->check(kNonNegativeSeed)
      ->capture_default_str();
  cmd->add_option("--input-lag", args.input_lag,
                       "lambda of G = (1-lambda)/(1-lambda q^-1) before the operator (Section 3.5.3)")
      ->check(kFinite & CLI::Range(0.0, 0.999))
      ->capture_default_str()
      ->excludes(plant);
  cmd->add_option("--noise-variance", args.noise_variance, "Override the scenario's noise variance")
      ->check(kFinite & CLI::NonNegativeNumber)
      ->excludes(plant);
  cmd->add_option("--out", args.data_out, "Recording to write (CSV, docs/data-format.md)")->required();
  cmd->add_option("--config-out", args.config_out, "Config to write (JSON, with the truth)")->excludes(plant);
  return cmd;
}

CLI::App* add_identify(CLI::App& app, IdentifyArgs& args) {
  auto* cmd = app.add_subcommand("identify", "Run DIS and/or AIS on a recording and print the estimates");
  cmd->add_option("--config", args.config, "Experiment config (JSON)")->required()->check(CLI::ExistingFile);
  cmd->add_option("--data", args.data, "Recording (CSV)")->required()->check(CLI::ExistingFile);
  cmd->add_option("--json", args.json_out, "Write the estimates as JSON");
  cmd->add_option("--scheme", args.scheme,
                  "Which scheme(s): dis, ais or both (each needs its phases), or auto: those whose phases the data "
                  "holds")
      ->check(CLI::IsMember({"dis", "ais", "both", "auto"}))
      ->capture_default_str();
  cmd->add_flag("--float", args.use_float, "Run the estimator in float32, as the firmware does");
  return cmd;
}

CLI::App* add_reproduce(CLI::App& app, ReproduceArgs& args) {
  auto* cmd = app.add_subcommand("reproduce", "Reproduce the paper's examples, Table 3 and the consistency check");
  cmd->add_option("--runs", args.runs, "Monte Carlo repetitions (Section 3.5.2)")
      ->check(CLI::Range(10, 100000))
      ->capture_default_str();
  cmd->add_option("--seed", args.seed, "Seed of the single runs")
      ->check(kNonNegativeSeed)
      ->capture_default_str();
  cmd->add_option("--json", args.json_out, "Write all numbers as JSON");
  return cmd;
}

CLI::App* add_diagnose(CLI::App& app, DiagnoseArgs& args) {
  auto* cmd = app.add_subcommand(
      "diagnose", "Simulate the identified model on 'val', find what it gets wrong, name the cause, extend, refit");
  cmd->add_option("--config", args.config, "Experiment config (JSON)")->required()->check(CLI::ExistingFile);
  cmd->add_option("--data", args.data, "Recording with all five phases (CSV)")->required()->check(CLI::ExistingFile);
  cmd->add_option("--json", args.json_out, "Write cause, parameters, fits, evidence and both models as JSON");
  cmd->add_option("--plot", args.plot_out, "Write a PNG: val simulations, residual correlations with bands");
  return cmd;
}

CLI::App* add_hidden_effect(CLI::App& app, HiddenEffectArgs& args) {
  auto* cmd = app.add_subcommand("hidden-effect", "Generate a random plant's recording with a hidden effect");
  cmd->add_option("--cause", args.cause,
                  "none, input_lag, dead_time, sensor_drift, colored_noise, operator_type, or several joined by '+' "
                  "(input_lag+sensor_drift; the pairs of docs/diagnose.md are the ones measured)")
      ->required();
  cmd->add_option("--borders", args.borders, "Borders between the levels: linear or curved")
      ->check(CLI::IsMember({"linear", "curved"}))
      ->capture_default_str();
  cmd->add_option("--seed", args.seed, "Seed of the plant, the effect's size and the noise")
      ->check(kNonNegativeSeed)
      ->capture_default_str();
  cmd->add_option("--out", args.data_out, "Recording to write (CSV)")->required();
  cmd->add_option("--config-out", args.config_out, "Config to write (JSON, without the effect)")->required();
  return cmd;
}

CLI::App* add_diagnose_sweep(CLI::App& app, DiagnoseSweepArgs& args) {
  auto* cmd = app.add_subcommand("diagnose-sweep",
                                       "Diagnose many hidden-effect recordings: hit rate per cause, confusion matrix");
  cmd->add_option("--seeds", args.seeds, "Recordings per cause")->check(CLI::Range(1, 10000))
      ->capture_default_str();
  cmd->add_option("--first-seed", args.first_seed, "First seed")->check(kNonNegativeSeed)->capture_default_str();
  cmd->add_option("--borders", args.borders, "Borders between the levels: linear or curved")
      ->check(CLI::IsMember({"linear", "curved"}))
      ->capture_default_str();
  cmd->add_flag("--pairs", args.pairs, "Hide two causes at once (the pairs of docs/diagnose.md)");
  cmd->add_option("--row", args.rows,
                  "Only this row of the table (its hidden causes, e.g. input_lag or input_lag+sensor_drift); "
                  "repeatable");
  cmd->add_option("--json", args.json_out, "Write the matrix and every case as JSON");
  cmd->add_flag("--verbose", args.verbose, "Print every case");
  cmd->add_flag("--oracle", args.oracle,
                "Also put the generator's plant on each true-structure fit's border tables and compare one-step "
                "errors and val fits (cases with input lag or dead time only; costs one more fit per case)");
  cmd->add_flag("--oracle-regimes", args.oracle_regimes,
                "Research, not a diagnosis: start every backlash fit of the input-lag search with the finer tables "
                "from the generator's plant (its regimes), to measure what a regime finder could gain");
  cmd->callback([&args] {
    if (args.first_seed > std::numeric_limits<std::uint64_t>::max() - static_cast<std::uint64_t>(args.seeds - 1)) {
      throw CLI::ValidationError("--first-seed", fmt::format("{} + --seeds {} passes 2^64 - 1", args.first_seed,
                                                              args.seeds));
    }
  });
  return cmd;
}

CLI::App* add_operator_fit(CLI::App& app, OperatorFitArgs& args) {
  auto* cmd = app.add_subcommand(
      "operator-fit",
      "Fit switch/backlash and a friction-gap operator to measured force-displacement CSVs (t_s, x_in, F_kip), "
      "test them on other files, run DIS/AIS with the fit as actuator (docs/friction-damper.md)");
  cmd->add_option("--train", args.train, "Training files (CSV)")->required()->check(CLI::ExistingFile);
  cmd->add_option("--test", args.test, "Test files (CSV), never used for fitting")->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--json", args.json_out, "Write the fits, models, causes and analysis as JSON");
  cmd->add_option("--plot", args.plot_out, "Write the measured and simulated loops as PNG (needs gnuplot)");
  cmd->add_option("--gnuplot", args.gnuplot, "gnuplot executable")->capture_default_str();
  cmd->add_option("--decimate", args.decimate,
                        "Resampling: replace every K samples by their mean (1: the data as recorded)")
      ->check(CLI::Range(1, 1000))->capture_default_str();
  cmd->add_option("--points", args.points, "Nodes of each fitted table (borders, G)")
      ->check(CLI::Range(2, 10000))->capture_default_str();
  cmd->add_option("--deadband", args.deadband,
                        "Reversal detection: v must retreat this far from its extreme (units of v)")
      ->check(kFinite & CLI::NonNegativeNumber)->capture_default_str();
  cmd->add_option("--reversal-window", args.reversal_window,
                        "Error analysis: 'reversal' = travel since the last reversal below this")
      ->check(kFinite & CLI::PositiveNumber)->capture_default_str();
  cmd->add_option("--engagement-window", args.engagement_window,
                        "Error analysis: 'engagement' = travel below this (and above the reversal window)")
      ->check(kFinite & CLI::PositiveNumber)->capture_default_str();
  cmd->add_flag("--no-stiffness", args.no_stiffness, "Extended model without the parallel stiffness k");
  cmd->add_option("--tension", args.tension,
                  "Band tension of a file, FILE=LB (FILE as given or its base name), for names without "
                  "'<T>lbtension' or to override it. With training files at two tensions or more, the friction-gap "
                  "operator is also fitted per tension and each test file is simulated at its own");
  return cmd;
}

CLI::App* add_design(CLI::App& app, DesignArgs& args) {
  auto* cmd = app.add_subcommand(
      "design",
      "Write a valid experiment config from n, m, the interval and a level count, or --check a config against the "
      "rules of the host and of the firmware image (docs/data-format.md)");
  auto* check = cmd->add_option("--check", args.check,
                                "Check this config instead: print a summary (T, lengths, samples of a firmware run, "
                                "whether host and image can run it); exit 1 naming the key and rule when not")
                    ->check(CLI::ExistingFile);
  const std::vector<CLI::Option*> design_options = {
      cmd->add_option("--n", args.n, "Order n of the linear subsystem"),
      cmd->add_option("--m", args.m, "Points m identified per border (levels of V_d and of V_a)"),
      cmd->add_option("--v-min", args.v_min, "v_min of the working interval")->check(kFinite),
      cmd->add_option("--v-max", args.v_max, "v_max of the working interval")->check(kFinite),
      cmd->add_option("--operator", args.op, "switch or backlash")->check(CLI::IsMember({"switch", "backlash"})),
      cmd->add_option("--levels", args.levels,
                      "K evenly spaced levels from v_min to v_max, both included (K >= m + 1; default m + 1): V_d "
                      "= the m lowest, V_a = the m highest"),
      cmd->add_option("--step-length", args.step_length, "L: each step experiment has L + 1 samples (L > n)")
          ->check(int64_as_typed(std::numeric_limits<int>::max()))->capture_default_str(),
      cmd->add_option("--pulse-length", args.pulse_length,
                      "N of both pulse experiments, >= 2T (default: the first whole number of periods >= 2000)")
          ->check(int64_as_typed(lashid::est::kMaxPulseLength)),
      cmd->add_option("--val-length", args.val_length, "Samples of the validation phase")
          ->check(int64_as_typed(std::numeric_limits<int>::max()))->capture_default_str(),
      cmd->add_option("--val-seed", args.val_seed, "Seed of the validation excitation (unsigned 32-bit)")
          ->check(int64_as_typed(std::numeric_limits<std::uint32_t>::max()))->capture_default_str(),
      cmd->add_option("--out", args.out, "Config to write (JSON)")};
  for (CLI::Option* option : design_options) check->excludes(option);
  // Writing needs the design; checking needs only the file.
  cmd->callback([cmd, &args] {
    if (!args.check.empty()) return;
    for (const char* name : {"--n", "--m", "--v-min", "--v-max", "--operator", "--out"}) {
      if (cmd->count(name) == 0) throw CLI::RequiredError(std::string(name) + " (or --check CONFIG)");
    }
  });
  return cmd;
}

}  // namespace

namespace {

// The diagnosis fits hundreds of models, each allocating and freeing a few MB (normal equations, residuals). With
// glibc's defaults the heap's top is returned to the system after each and faulted in again: 2,000 brk calls
// and 0.6 s of system time in a 2.5 s diagnosis (session 6's measurement, not repeated since; the policy is listed in
// docs/diagnose-history.md, "Time, session by session"). A 64 MB top pad and a 256 MB trim threshold keep the pages:
// the same diagnosis took 1.8 s.
void keep_freed_heap_pages() {
#if defined(__GLIBC__)
  mallopt(M_TOP_PAD, 64 << 20);
  mallopt(M_TRIM_THRESHOLD, 256 << 20);
#endif
}

}  // namespace

int main(int argc, char** argv) {
  keep_freed_heap_pages();
  CLI::App app{"lashid: DIS/AIS identification of Hammerstein-like systems with switch or backlash nonlinearities\n"
               "(Giri et al., Automatica; nonparametric borders). See README.md and docs/."};
  app.require_subcommand(1);
  app.set_version_flag("--version", fmt::format("lashid {}", LASHID_VERSION));
  Arguments a;
  // Each subcommand and the function that runs it with its parsed arguments.
  const std::vector<std::pair<CLI::App*, std::function<int()>>> commands = {
      {app.add_subcommand("scenarios", "List the built-in simulation scenarios"), [] { return run_scenarios(); }},
      {add_simulate(app, a.simulate), [&] { return run_simulate(a.simulate); }},
      {add_identify(app, a.identify), [&] { return run_identify(a.identify); }},
      {add_reproduce(app, a.reproduce), [&] { return run_reproduce(a.reproduce); }},
      {add_hil(app, a.hil), [&] { return run_hil_command(a.hil); }},
      {add_qemu_command(app, a.qemu_command), [&] { return run_qemu_command(a.qemu_command); }},
      {add_diagnose(app, a.diagnose), [&] { return run_diagnose(a.diagnose); }},
      {add_hidden_effect(app, a.hidden_effect), [&] { return run_hidden_effect(a.hidden_effect); }},
      {add_diagnose_sweep(app, a.diagnose_sweep), [&] { return run_diagnose_sweep(a.diagnose_sweep); }},
      {add_operator_fit(app, a.operator_fit), [&] { return run_operator_fit(a.operator_fit); }},
      {add_design(app, a.design), [&] { return run_design(a.design); }},
  };
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (dynamic_cast<const CLI::RequiredError*>(&e) != nullptr) {
      if (const std::optional<std::string> word = unknown_word(app, argc, argv)) {
        fmt::print(stderr, "{}\nRun with --help for more information.\n", *word);
        return static_cast<int>(CLI::ExitCodes::ExtrasError);
      }
    }
    return app.exit(e);
  }
  try {
    for (const auto& [subcommand, run] : commands) {
      if (!*subcommand) continue;
      refuse_overwriting_own_files(*subcommand);
      return run();
    }
  } catch (const std::bad_alloc&) {
    std::fflush(stdout);
    fmt::print(stderr, "lashid: error: out of memory: the input asks for more than this machine holds (a config's "
                       "lengths, e.g. val_length, or a recording's size)\n");
    return 1;
  } catch (const lashid::sim::Interrupted& e) {
    // A hil or simulate run the user stopped, cleaned up: 128 + the signal, as a shell reports a command a signal ended.
    std::fflush(stdout);
    fmt::print(stderr, "lashid: error: {}\n", e.what());
    return 128 + e.signal();
  } catch (const std::exception& e) {
    std::fflush(stdout);
    fmt::print(stderr, "lashid: error: {}\n", e.what());
    return 1;
  }
  return 0;
}
