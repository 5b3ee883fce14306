// `lashid hil`: the firmware in QEMU identifies the plant the host plays over the emulated UART.
#include <algorithm>
#include <cstdio>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "lashid/estimator/status.hpp"
#include "lashid/hil/config_design.hpp"
#include "lashid/hil/hil.hpp"
#include "lashid/hil/verdict.hpp"
#include "lashid/io/config.hpp"
#include "lashid/io/data_error.hpp"
#include "lashid/io/files.hpp"
#include "lashid/io/json.hpp"
#include "lashid/io/plant_file.hpp"
#include "lashid/report/json.hpp"
#include "lashid/report/report.hpp"
#include "lashid/sim/scenario.hpp"
#include "hil_references.hpp"
#include "plant_notes.hpp"

namespace lashid::app {

using namespace lashid::sim;

namespace {

// kDone's status byte, or -1 when no kDone frame arrived.
const char* run_status_name(int s) { return s < 0 ? "no report" : fw::to_string(static_cast<fw::RunStatus>(s)); }

void print_estimate(const fw::EstimateRecord& e, const ExperimentConfig& config) {
  const bool dis = e.scheme == est::Scheme::kDescending;
  const auto& V = dis ? config.V_d : config.V_a;
  const Truth* truth = config.truth ? &*config.truth : nullptr;
  const auto cell = [](const std::vector<double>* v, std::size_t k) {
    return v != nullptr && k < v->size() ? fmt::format("{:>11.5g}", (*v)[k]) : std::string();
  };
  const auto status = static_cast<lashid::est::Status>(e.status);
  if (status != lashid::est::Status::kOk) {
    // The firmware sends no values for a failed scheme (NaN): the status is the whole answer.
    fmt::print("  {} estimate (status {}): no values\n", dis ? "DIS" : "AIS", lashid::est::to_string(status));
    return;
  }
  fmt::print("  {} estimate (status {}): ybar0 {:.4g}, residual variance {:.4g}\n", dis ? "DIS" : "AIS",
             lashid::est::to_string(status), e.ybar0, e.noise_variance);
  fmt::print("    {:<10}{:>11}{:>11}{:>11}\n", "", "firmware", "std.err", truth ? "truth" : "");
  for (std::size_t i = 0; i < e.n; ++i) {
    fmt::print("    {:<10}{:>11.5g}{:>11.2g}{}\n", fmt::format("a{}", i + 1), e.a[i], e.se_a[i],
               cell(truth ? &truth->a : nullptr, i));
  }
  for (std::size_t i = 0; i < e.n; ++i) {
    fmt::print("    {:<10}{:>11.5g}{:>11.2g}{}\n", fmt::format("b{}", i + 1), e.b[i], e.se_b[i],
               cell(truth ? &truth->b : nullptr, i));
  }
  const std::vector<std::string> labels = lashid::report::level_labels(V);  // as many digits as tell them apart
  for (std::size_t j = 0; j < e.m && j < V.size(); ++j) {
    fmt::print("    {:<10}{:>11.5g}{:>11}{}\n", labels[j], e.F[j], "",
               cell(truth ? (dis ? &truth->F_d : &truth->F_a) : nullptr, j));
  }
}

// As the firmware reported it: a failed scheme's values are NaN on the link, null here.
nlohmann::json estimate_json(const fw::EstimateRecord& e) {
  const auto first = [](const auto& values, std::size_t count) {
    return std::vector<float>(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(count));
  };
  return {{"a", first(e.a, e.n)},
          {"b", first(e.b, e.n)},
          {"F", first(e.F, e.m)},
          {"se_a", first(e.se_a, e.n)},
          {"se_b", first(e.se_b, e.n)},
          {"ybar0", e.ybar0},
          {"noise_variance", e.noise_variance},
          {"status", e.status},
          {"status_name", lashid::est::to_string(static_cast<lashid::est::Status>(e.status))}};
}

// The --json of a run that ended in an error: no estimates, the verdict failed, and why.
nlohmann::json error_json(const std::string& what) {
  return {{"verdict", {{"ok", false}, {"failures", {"error"}}}}, {"error", what}};
}

// The command once its --json is known writable.
int run_checked_hil(const HilArgs& args) {
  std::optional<std::vector<fw::EstimateRecord>> expected_records;
  if (!args.expect_estimates.empty()) expected_records = read_expected_estimates(args.expect_estimates);
  // The design: the config's (checked on the host unless --unchecked-design), else the scenario's. The plant: the
  // plant file's, else the scenario's. The config also names the levels printed and identifies the recording.
  const Scenario* scenario = args.scenario.empty() ? nullptr : &find_scenario(args.scenario);
  std::optional<ExperimentConfig> config;
  std::optional<fw::RunDesign> design;
  if (!args.config.empty()) {
    config = read_config_json(args.config, ConfigLimits{.max_order = fw::kMaxOrder,
                                                        .max_points = fw::kMaxPoints,
                                                        .range_name = "the firmware image's capacity"});
    design = args.unchecked_design ? run_design_as_is(*config, experiment_lengths(*config), args.config)
                                   : to_run_design(*config, args.config);
  }
  HilOptions options;
  options.design = design;
  options.firmware = args.firmware;
  if (!args.attach.empty()) options.attach_link = args.attach[0];
  if (args.attach.size() == 2) options.attach_plant = args.attach[1];
  options.physical_plant = args.physical_plant;
  options.scenario = args.scenario;
  options.seed = args.seed;
  options.machine = args.machine;
  options.qemu = args.qemu;
  options.timeout_seconds = args.timeout;
  options.corrupt_every = args.corrupt_every;
  options.fault_rate = args.fault_rate;
  options.fault_seed = static_cast<std::uint64_t>(args.fault_seed);
  options.icount = args.icount;
  options.on_progress = [](fw::Stage stage, std::uint32_t samples) {
    fmt::print("  [firmware] {} (after {} samples)\n", fw::to_string(stage), samples);
    std::fflush(stdout);
  };
  options.plant_file = args.plant;
  options.record = args.record;
  if (!args.plant.empty()) note_ignored_keys(read_plant_json(args.plant), args.plant);
  const HilResult r = run_hil(options);
  std::optional<HilResult> host;
  if (args.compare_host) {
    HilOptions in_process = options;  // the same plant, not recorded again
    in_process.record.clear();
    host = run_on_host_board(in_process);
  }
  JudgeOptions rules;
  rules.attached = !options.attach_link.empty();
  rules.tolerance = args.tolerance;
  rules.plant_played = !args.physical_plant;
  rules.streamed = args.physical_plant && !args.record.empty();
  rules.compare_host = args.compare_host;
  HilVerdict verdict = judge(r, host ? &*host : nullptr, rules);
  // --record: the recording must be what the firmware estimated from (identify --float on it, relative 1e-3), with
  // the samples the firmware set aside left out as it did (without_set_aside). A streamed run must have named every
  // one it counted; otherwise the two are not compared, and that is said.
  const ExperimentConfig* identified_with = config ? &*config : scenario != nullptr ? &scenario->config : nullptr;
  std::string recording_unreadable;
  const std::uint32_t set_aside = r.cost ? r.cost->bad_sensor_values : 0;
  const bool comparable = !args.physical_plant || r.set_aside.size() == set_aside;
  if (!args.record.empty() && r.recording_complete && comparable && identified_with != nullptr &&
      (verdict.dis || verdict.ais) &&
      identified_with->n <= kMaxOrder && identified_with->m <= kMaxPoints) {
    try {
      const fw::RunDesign sent = design ? *design : run_design_of(*scenario);
      verdict.recording = compare_with_recording(
          r, verdict, identify_recording(*identified_with, args.record, r.estimates, sent, r.set_aside),
          args.tolerance);
      if (!verdict.recording->equal) verdict.failures.push_back(HilFailure::kDifferentFromRecording);
    } catch (const DataError& e) {
      // The host cannot identify what the firmware recorded (e.g. a sample beyond the estimator's range): a failed
      // check of this run, not an error that would lose its verdict and its JSON.
      recording_unreadable = e.what();
      verdict.failures.push_back(HilFailure::kDifferentFromRecording);
    }
  }
  std::optional<RecordingComparison> expected;
  if (expected_records) {
    expected = compare_with_recording(r, verdict, *expected_records, 0.0);
    if (!expected->equal) verdict.failures.push_back(HilFailure::kDifferentFromExpected);
  }

  const std::string board =
      args.firmware.empty() ? std::string("attached board") : fmt::format("{} on {}", args.firmware, args.machine);
  fmt::print("== hil: {}, design {}, plant {} ==\n", board, args.config.empty() ? args.scenario : args.config,
             args.physical_plant ? std::string("physical (the board's own actuator and sensor)")
                                 : fmt::format("{} (seed {})", args.plant.empty() ? args.scenario : args.plant,
                                               args.seed));
  if (rules.attached) {
    fmt::print("  firmware result: {}; QEMU is not this command's (attached): its exit status is not known\n",
               run_status_name(r.done));
  } else {
    fmt::print("  firmware result: {}; QEMU exit status {}{}\n", run_status_name(r.done), r.qemu_exit,
               r.qemu_exit > 128 ? fmt::format(" (QEMU was killed by signal {})", r.qemu_exit - 128) : "");
  }
  if (r.design_status > 0) {
    fmt::print("  the firmware refused the design: {}\n",
               fw::to_string(static_cast<fw::DesignStatus>(r.design_status)));
  }
  if (args.physical_plant) {
    fmt::print("  host: the plant is the board's; {} samples streamed, {} protocol errors on the link\n", r.samples,
               r.protocol_errors);
  } else {
    fmt::print("  host: {} plant samples, {} repeated requests answered from cache, {} protocol errors, {} frames "
               "damaged on purpose\n",
               r.samples, r.repeated_requests, r.protocol_errors, r.corrupted_by_host);
  }
  if (args.fault_rate > 0) {
    fmt::print("  link faults (rate {:g}, seed {}): {} of {} bytes ({} dropped, {} garbled, {} duplicated); detected: "
               "{} frames by the host, {} by the firmware; sent again: {} by the host, {} plant requests by the "
               "firmware\n",
               args.fault_rate, args.fault_seed, r.faults.injected(), r.faults.bytes, r.faults.dropped,
               r.faults.flipped, r.faults.duplicated, r.protocol_errors, r.cost ? r.cost->link_errors : 0,
               r.host_retries, r.cost ? r.cost->retries : 0);
  }
  if (!args.record.empty()) {
    const bool none_streamed = args.physical_plant && r.samples == 0 && r.cost && r.cost->samples > 0;
    if (r.recorded == 0 && none_streamed) {
      fmt::print("  no recording written: the firmware measured {} samples but streamed none: its board does not "
                 "stream (hal::BuffersLinkWrites: the STM32F405 analog image streams at sample rates its link can "
                 "carry, up to 1,200 Hz; docs/platform.md) ({} keeps what it held)\n",
                 r.cost->samples, args.record);
    } else if (r.recorded == 0 && r.cost && r.cost->samples > 0) {
      fmt::print("  no recording written: the run ended before its first phase ({} samples measured, in the interval "
                 "check) ({} keeps what it held)\n",
                 r.cost->samples, args.record);
    } else if (r.recorded == 0) {
      fmt::print("  no recording written: not a sample was measured ({} keeps what it held)\n", args.record);
    } else {
      const bool lost = verdict.has(HilFailure::kRecordingIncomplete);
      fmt::print("  recorded {} samples to {}{}\n", r.recorded, args.record,
                 r.recording_complete ? ""
                 : lost ? fmt::format(" (partial: {} of the {} samples the firmware measured were streamed; a lost "
                                      "sample block is not sent again)",
                                      r.samples, r.cost->samples)
                        : " (partial: the run stopped before the design's end)");
    }
  }
  if (!args.record.empty() && r.recording_complete && !comparable) {
    fmt::print("  on-device estimates vs `lashid identify --float` on {}: not compared: the firmware set aside {} bad "
               "sensor values and named {}\n",
               args.record, set_aside, r.set_aside.size());
  }
  if (!recording_unreadable.empty()) {
    fmt::print("  the recording could not be identified on the host: {}\n", recording_unreadable);
  }
  // The truth printed is the scenario's only when its plant was played.
  ExperimentConfig shown = config ? *config : scenario->config;
  if (!args.plant.empty() || config) shown.truth.reset();
  for (const auto& e : r.estimates) print_estimate(e, shown);
  nlohmann::json out;
  if (r.cross_check) {
    const auto& c = *r.cross_check;
    if (c.max_z < 0) {
      fmt::print("  cross-check (Remark 3b): not available (a scheme failed)\n");
      out["cross_check"] = nullptr;
    } else {
      // The order n from a usable estimate (none may have arrived: the index is then printed as it is).
      const std::optional<std::size_t> k = verdict.dis ? verdict.dis : verdict.ais;
      const std::string worst = cross_check_parameter(c.worst, k ? r.estimates[*k].n : 0);
      fmt::print("  cross-check (Remark 3b): max |DIS - AIS| / se = {:.2f} on {} (threshold {:.1f}): {}\n", c.max_z,
                 worst, c.threshold,
                 c.disagree ? "DISAGREE: the nonlinearity is not the assumed switch/backlash" : "agree");
      out["cross_check"] = {
          {"max_z", c.max_z}, {"threshold", c.threshold}, {"disagree", c.disagree != 0}, {"worst", worst}};
    }
  }
  if (r.cost) {
    const auto& c = *r.cost;
    const double per_update = c.updates ? static_cast<double>(c.update_cycles) / c.updates : 0.0;
    const double per_solve = c.solves ? static_cast<double>(c.solve_cycles) / c.solves : 0.0;
    const double amortised = c.updates ? static_cast<double>(c.update_cycles + c.solve_cycles) / c.updates : 0.0;
    fmt::print("  firmware: {} samples, link errors {}, retries {}, stack high-water {} bytes, bad sensor values {}, "
               "samples rejected by the estimator {}, reports not sent {}\n",
               c.samples, c.link_errors, c.retries, c.stack_bytes, c.bad_sensor_values, c.rejected_samples,
               c.send_failures);
    fmt::print("  cost (board cycles{}): update {:.1f}/sample, solve {:.0f}/call ({} calls), amortised {:.1f}/sample\n",
               args.icount ? "" : "; without --icount SysTick follows host time: not an instruction count",
               per_update, per_solve, c.solves, amortised);
    if (args.ticks_to_instructions > 0) {
      fmt::print("  cost (instructions, x{:g}): update {:.0f}/sample, solve {:.0f}/call, amortised {:.0f}/sample\n",
                 args.ticks_to_instructions, per_update * args.ticks_to_instructions,
                 per_solve * args.ticks_to_instructions, amortised * args.ticks_to_instructions);
    }
    out["cost"] = {{"update_cycles", c.update_cycles}, {"updates", c.updates},   {"solve_cycles", c.solve_cycles},
                   {"solves", c.solves},               {"samples", c.samples},   {"link_errors", c.link_errors},
                   {"retries", c.retries},             {"stack_bytes", c.stack_bytes},
                   {"rejected_samples", c.rejected_samples}, {"send_failures", c.send_failures},
                   {"bad_sensor_values", c.bad_sensor_values}};
  }
  for (const auto& e : r.estimates) out[e.scheme == est::Scheme::kDescending ? "dis" : "ais"] = estimate_json(e);
  out["done"] = r.done;
  out["done_name"] = run_status_name(r.done);
  out["design_status"] = r.design_status;
  out["design_status_name"] =
      r.design_status < 0 ? "no answer" : fw::to_string(static_cast<fw::DesignStatus>(r.design_status));
  out["qemu_exit"] = r.qemu_exit;

  if (verdict.host) {
    const HostComparison& h = *verdict.host;
    fmt::print("  QEMU vs host build of the same firmware: {} vs {} samples, max relative difference {:.2g} "
               "(tolerance {:.0e}): {}\n",
               h.samples, h.host_samples, h.max_relative_difference, args.tolerance, h.equal ? "equal" : "DIFFERENT");
    out["host_relative_difference"] = h.max_relative_difference;
  }
  if (verdict.recording) {
    fmt::print("  on-device estimates vs `lashid identify --float` on {}: max relative difference {:.2g} "
               "(tolerance {:.0e}): {}\n",
               args.record, verdict.recording->max_relative_difference, args.tolerance,
               verdict.recording->equal ? "equal" : "DIFFERENT");
    out["recording_relative_difference"] = verdict.recording->max_relative_difference;
  }
  if (args.fault_rate > 0) {
    // injected: bytes damaged on purpose; detected: frames dropped by a checksum or length check or out of turn,
    // on either side; retries: requests sent again after a loss, by the host and by the firmware.
    const std::uint32_t firmware_errors = r.cost ? r.cost->link_errors : 0, firmware_retries = r.cost ? r.cost->retries : 0;
    out["faults"] = {{"rate", args.fault_rate},
                     {"seed", args.fault_seed},
                     {"injected", r.faults.injected()},
                     {"dropped", r.faults.dropped},
                     {"garbled", r.faults.flipped},
                     {"duplicated", r.faults.duplicated},
                     {"bytes", r.faults.bytes},
                     {"detected", std::uint64_t{r.protocol_errors} + firmware_errors},
                     {"retries", std::uint64_t{r.host_retries} + firmware_retries}};
  }
  if (expected) {
    fmt::print("  estimates vs {}: max relative difference {:.2g}: {}\n", args.expect_estimates,
               expected->max_relative_difference, expected->equal ? "identical" : "DIFFERENT");
    out["expected_relative_difference"] = expected->max_relative_difference;
  }
  if (verdict.fault_injection) {
    const FaultInjection& f = *verdict.fault_injection;
    fmt::print("  fault injection: {} frames damaged, {} re-requested by the firmware: {}\n", f.damaged,
               f.re_requested, f.all_detected ? "all detected" : "NOT ALL DETECTED");
  }
  std::vector<std::string> failures;
  for (const HilFailure f : verdict.failures) failures.emplace_back(to_string(f));
  fmt::print("  verdict: {}\n", verdict.ok() ? "pass" : fmt::format("FAIL ({})", fmt::join(failures, "; ")));
  out["verdict"] = {{"ok", verdict.ok()}, {"failures", failures}};
  if (!args.json_out.empty()) write_json_file(args.json_out, out);
  if (!r.console.empty()) fmt::print("  firmware console:\n{}", r.console);
  return verdict.ok() ? 0 : 1;
}

}  // namespace

int run_hil_command(const HilArgs& args) {
  // What can be checked before the run is, so that a mistake does not cost the run and its results.
  if (!args.json_out.empty()) check_can_write(args.json_out);
  try {
    return run_checked_hil(args);
  } catch (const std::exception& e) {
    // A command that ends in an error replaces an earlier --json too: a script that reads only the file must not
    // see an old pass.
    if (!args.json_out.empty()) {
      try {
        write_json_file(args.json_out, error_json(e.what()));
      } catch (const std::exception& w) {
        // The run's error stays the one reported; the file's failure is said beside it.
        fmt::print(stderr, "lashid: note: {} could not be replaced by the error's JSON: {}\n", args.json_out, w.what());
      }
    }
    throw;
  }
}

int run_qemu_command(const QemuCommandArgs& args) {
  QemuCommand command;
  command.qemu = args.qemu;
  command.machine = args.machine;
  command.serials = args.serials;
  command.icount = args.icount;
  command.kernel = args.kernel;
  // Checked as hil checks it: a command line for an image QEMU cannot run is no help.
  check_firmware_image(command.kernel, command.machine, "qemu-command");
  // One argument per line, for `mapfile -t` in scripts (paths with spaces stay one argument).
  for (const std::string& arg : qemu_command_line(command)) fmt::print("{}\n", arg);
  return 0;
}

}  // namespace lashid::app
