// The options of `lashid hil` and `lashid qemu-command` (cli_options.hpp).
#include "cli_options.hpp"

#include "cli_checks.hpp"

namespace lashid::app {

CLI::App* add_hil(CLI::App& app, HilArgs& args) {
  auto* cmd = app.add_subcommand("hil",
                                 "Run the firmware in QEMU (or attach to a board) and play the actuator and plant over "
                                 "its UART, or drive a board with its own (--physical-plant)");
  auto* fw_opt = cmd->add_option("--firmware", args.firmware, "Firmware ELF to start QEMU with (cross preset build)")
                    ->check(CLI::ExistingFile);
  auto* attach_opt = cmd->add_option("--attach", args.attach,
                                         "Attach instead of starting QEMU: LINK and PLANT are a running QEMU's "
                                         "UART0 and UART1 Unix sockets (-serial unix:LINK,server=on,wait=off "
                                         "-serial unix:PLANT,server=on,wait=off), or two serial ports, a board's "
                                         "link and plant-port UARTs (e.g. /dev/ttyUSB0 /dev/ttyUSB1; 115200 baud, "
                                         "8N1, raw); with --physical-plant the link only")
                         ->expected(1, 2);
  fw_opt->excludes(attach_opt);
  auto* scenario = cmd->add_option("--scenario", args.scenario,
                                   "Built-in plant played by the host and design sent to the firmware (lashid "
                                   "scenarios); --config and --plant replace either part");
  auto* config = cmd->add_option("--config", args.config,
                                 "Experiment config (JSON) whose design is sent to the firmware (docs/data-format.md: "
                                 "levels, lengths, validation phase)")
                     ->check(CLI::ExistingFile);
  cmd->add_flag("--unchecked-design", args.unchecked_design,
                "Send the config's design without the host's check of its rules in float32: the firmware's own check "
                "answers (for testing it; a refused design runs nothing). The config file's own rules still apply")
      ->needs(config);
  auto* physical = cmd->add_flag("--physical-plant", args.physical_plant,
                                 "The board drives its own actuator and reads its own sensor (an analog image, e.g. "
                                 "the STM32F405's lashid_fw_analog.elf: DAC out, ADC in): nothing is played, the "
                                 "design (--config) is sent and the reports read on the link alone; with --record the "
                                 "firmware streams every sample it measured")
                       ->needs(config)
                       ->excludes(scenario);
  // One callback per subcommand (a second call of callback() replaces the first).
  cmd->callback([&args] {
    if (args.firmware.empty() && args.attach.empty()) throw CLI::RequiredError("--firmware or --attach");
    if (args.config.empty() && args.scenario.empty()) throw CLI::RequiredError("--scenario or --config");
    if (args.plant.empty() && args.scenario.empty() && !args.physical_plant) {
      throw CLI::RequiredError("--scenario, --plant or --physical-plant");
    }
    if (args.attach.size() == 1 && !args.physical_plant) {
      throw CLI::ValidationError("--attach", "give LINK and PLANT (the link alone only with --physical-plant)");
    }
    if (args.attach.size() == 2 && args.physical_plant) {
      throw CLI::ValidationError("--attach", "a physical plant has no plant port: give the link only");
    }
  });
  auto* plant = cmd->add_option("--plant", args.plant,
                                "Play this plant file (JSON, docs/data-format.md) instead of the scenario's")
                    ->check(CLI::ExistingFile);
  cmd->add_option("--record", args.record,
                  "Write every exchanged sample (v commanded, y answered; with --physical-plant, as the firmware "
                  "streams them) as a recording (CSV), flushed while the run goes on; a run that stops early keeps "
                  "what it measured (marked partial)");
  physical->excludes(plant);
  cmd->add_option("--seed", args.seed, "Noise seed of the plant")->check(kNonNegativeSeed)->capture_default_str();
  cmd->add_option("--machine", args.machine,
                  "QEMU machine: mps2-an386 (M4F), mps2-an500 (M7), mps2-an385 (M3), netduinoplus2 (STM32F405)")
      ->capture_default_str();
  cmd->add_option("--qemu", args.qemu, "QEMU executable")->capture_default_str();
  cmd->add_option("--timeout", args.timeout, "Wall-clock limit in seconds")
      ->check(kFinite & CLI::Range(0.001, 1e6))
      ->capture_default_str();
  physical->excludes(cmd->add_option("--corrupt-every", args.corrupt_every,
                                     "Fault injection: damage every k-th measurement frame (the firmware must detect "
                                     "it)")
                         ->check(CLI::NonNegativeNumber));
  cmd->add_option("--fault-rate", args.fault_rate,
                  "Fault injection: drop, garble or duplicate each byte on both UARTs, both ways, with this "
                  "probability (checked, re-sent; a link that is too bad ends the run with a named failure)")
      ->check(kFinite & CLI::Range(0.0, 1.0));
  cmd->add_option("--fault-seed", args.fault_seed, "Seed of --fault-rate's draws")->check(kNonNegativeSeed)
      ->capture_default_str();
  cmd->add_option("--expect-estimates", args.expect_estimates,
                  "An earlier run's --json (e.g. the clean run of a fault-injection test): the estimates must equal "
                  "its own exactly, bit for bit")
      ->check(CLI::ExistingFile);
  physical->excludes(cmd->add_flag("--compare-host", args.compare_host,
                                   "Also run the same firmware on the in-process host board and require equal "
                                   "estimates"));
  cmd->add_option("--tolerance", args.tolerance, "Relative tolerance of --compare-host, and of --record's check against identify --float")
      ->check(kFinite & CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_option("--ticks-to-instructions", args.ticks_to_instructions,
                      "Convert the board's cycle counts to instructions (QEMU -icount shift=0, SysTick at 25 MHz: 40; "
                      "at 168 MHz, netduinoplus2: 5.952381)")
      ->check(kFinite & CLI::NonNegativeNumber);
  cmd->add_flag("--icount", args.icount,
                    "Run QEMU with -icount shift=0 (deterministic cycle counts; much slower exchanges)");
  cmd->add_option("--json", args.json_out, "Write the results as JSON");
  return cmd;
}

CLI::App* add_qemu_command(CLI::App& app, QemuCommandArgs& args) {
  auto* cmd = app.add_subcommand(
      "qemu-command", "Print the qemu-system-arm command line for an image, one argument per line (cmake/Qemu.cmake)");
  cmd->add_option("--kernel", args.kernel, "Firmware ELF")->required();
  cmd->add_option("--machine", args.machine, "QEMU machine")->capture_default_str();
  cmd->add_option("--qemu", args.qemu, "QEMU executable")->capture_default_str();
  cmd->add_option("--serial", args.serials, "-serial backend of the next UART (UART0 first); repeatable");
  cmd->add_flag("--icount", args.icount, "Add -icount shift=0 (deterministic instruction counts)");
  return cmd;
}

}  // namespace lashid::app
