// Host-in-the-loop: the identification firmware runs on an emulated Cortex-M (QEMU mps2) and the host plays the
// actuator and the plant on the other end of its UART1 (one kActuate/kMeasurement exchange per sample), while
// UART0 carries the start command and the firmware's reports (hal/link_protocol.hpp, firmware/messages.hpp).
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "lashid/firmware/messages.hpp"
#include "lashid/firmware/run_design.hpp"
#include "lashid/hal/host_board.hpp"
#include "lashid/io/stop_signals.hpp"
#include "lashid/hil/any_plant.hpp"
#include "lashid/hil/link_faults.hpp"
#include "lashid/io/config.hpp"
#include "lashid/sim/scenario.hpp"

namespace lashid::sim {

struct HilOptions {
  std::string firmware;                 ///< the firmware ELF (QEMU is started with it, unless attaching)
  /// Attach instead of starting QEMU: the Unix sockets of a QEMU started by the user with
  /// `-serial unix:LINK,server=on,wait=off -serial unix:PLANT,server=on,wait=off` (UART0, UART1). The session
  /// ends at the firmware's kDone frame; QEMU's exit status is then unknown (qemu_exit stays -1).
  std::string attach_link;
  std::string attach_plant;
  std::string scenario;                 ///< the plant the host plays (dis_paper, ais_paper, ...)
  /// The design sent to the firmware before the start; none: the scenario's (run_design_of).
  std::optional<fw::RunDesign> design;
  std::uint64_t seed = 1;
  std::string machine = "mps2-an386";   ///< QEMU machine
  std::string qemu = "qemu-system-arm";
  double timeout_seconds = 300;         ///< wall-clock limit for the whole run; QEMU is killed after it
  int corrupt_every = 0;                ///< > 0: flip one bit in every k-th measurement frame (fault injection)
  /// > 0: each byte on each direction of both UARTs is dropped, garbled or duplicated with this probability
  /// (link_faults.hpp), drawn from fault_seed.
  double fault_rate = 0;
  std::uint64_t fault_seed = 1;
  bool icount = false;                  ///< QEMU -icount shift=0: deterministic cycle counts, much slower I/O
  /// Called on each kStatus frame (the firmware announces every stage change): progress while the run goes on.
  std::function<void(fw::Stage stage, std::uint32_t samples)> on_progress;
  // Issue 10, plant files and recording:
  std::string plant_file;               ///< play this plant file (io/plant_file.hpp) instead of the scenario's plant
  std::string record;                   ///< write every exchanged sample here as a recording (run_recording.hpp)
  /// The board drives a physical actuator and reads a physical sensor (an analog image such as the STM32F405's
  /// lashid_fw_analog): no plant is played and no plant port is opened (QEMU's second UART goes to null; attaching
  /// takes the link only). The host sends the design and collects the reports; with `record`, the start asks the
  /// firmware to stream every sample it measures (kStartStreamSamples) and the recording is made of them. No
  /// host-board comparison.
  bool physical_plant = false;
};

struct HilResult {
  std::vector<fw::EstimateRecord> estimates;  ///< in the order received (DIS, then AIS)
  std::optional<fw::CrossCheckRecord> cross_check;
  std::optional<fw::CostRecord> cost;
  int design_status = -1;             ///< fw::DesignStatus the firmware answered to the design, -1 if none arrived
  int done = -1;                      ///< fw::RunStatus of the kDone frame, -1 if none arrived
  int qemu_exit = -1;                 ///< QEMU's exit status (the firmware's semihosting exit code)
  std::uint32_t samples = 0;          ///< plant steps taken by the host
  std::uint32_t repeated_requests = 0;  ///< kActuate for an already answered t (answered from the cache)
  std::uint32_t protocol_errors = 0;  ///< frames the host dropped (checksum/length) or could not use
  std::uint32_t corrupted_by_host = 0;  ///< frames deliberately damaged (corrupt_every)
  FaultCounts faults;                 ///< bytes dropped, garbled and duplicated on purpose (fault_rate)
  /// The design, the start, a report request or a query the host sent again because its answer did not come.
  std::uint32_t host_retries = 0;
  std::string console;                ///< what the firmware printed (semihosting)
  std::uint64_t recorded = 0;         ///< samples written to HilOptions::record
  /// Streamed runs (physical plant): the run's sample indices the firmware set aside as bad sensor values (a clipped
  /// or out-of-range reading); the recording holds them as measured.
  std::vector<std::uint64_t> set_aside;
  bool recording_complete = false;    ///< every sample of the design's phases was recorded
};

/// A qemu-system-arm command line for an mps2 image: the machine, the project's machine-independent flags
/// (cmake/Qemu.cmake: -nographic -monitor none -semihosting-config ...), -icount shift=0 on request, one -serial per
/// UART in order (UART0, UART1, ...), and the image.
struct QemuCommand {
  std::string qemu = "qemu-system-arm";
  std::string machine = "mps2-an386";
  std::vector<std::string> serials;  ///< QEMU -serial backends: "unix:PATH", "null", "stdio", ...
  bool icount = false;
  std::string kernel;                ///< the image (ELF)
};
/// The program followed by its arguments.
std::vector<std::string> qemu_command_line(const QemuCommand& command);

/// The phase lengths of a firmware run: those of a config (experiment_lengths), one L for both step experiments.
using RunLengths = ExperimentLengths;

/// The design of a firmware run for `config` (float32, as the firmware holds it) with `lengths`
/// (run_design_as_is of config_design.hpp, then fw::check_design). Throws std::invalid_argument naming the key and
/// the rule when the firmware would refuse it, e.g. n or m beyond the image's capacity, or a config without V_d or
/// V_a (the firmware runs both schemes). For a config file with its own lengths: to_run_design(config, source_name).
fw::RunDesign to_run_design(const ExperimentConfig& config, const RunLengths& lengths);

/// The design of `scenario`'s experiments (its config and lengths, no validation phase): what `lashid hil
/// --scenario` sends. Throws std::invalid_argument as to_run_design, or when the scenario's two step experiments
/// differ in length (the firmware has one L).
fw::RunDesign run_design_of(const Scenario& scenario);

/// run_hil stopped by SIGINT, SIGTERM or SIGHUP: QEMU was killed, the session's sockets removed, and the recording
/// kept as after any early stop (marked partial; the message says where). signal(): the signal's number (the CLI
/// exits with 128 + signal, as a shell reports a command a signal ended).
class HilInterrupted : public Interrupted {
 public:
  using Interrupted::Interrupted;
};

/// What can be known of an image before QEMU boots it: it exists, is an ARM ELF, is whole (not cut short), and was
/// built for `machine` (its section .lashid.machine, when it has one). Throws std::runtime_error naming what is wrong,
/// after `command` (the subcommand that asks: "hil", "qemu-command").
void check_firmware_image(const std::string& firmware, const std::string& machine, std::string_view command);

/// Runs QEMU with the firmware, sends the design, and plays the scenario's plant (or options.plant_file's),
/// recording the exchanged samples to options.record if set (also when the run stops early: the recording is then
/// marked partial). Throws std::runtime_error when QEMU cannot be started, a socket fails, or the time limit is
/// exceeded, or when the image names another machine than options.machine (its section .lashid.machine);
/// std::invalid_argument when the design cannot be made (run_design_of); HilInterrupted on SIGINT, SIGTERM or SIGHUP.
HilResult run_hil(const HilOptions& options);

/// The firmware's board on the PC with the played plant in-process (a scenario's or a plant file's): the same plant
/// `lashid hil` plays over the UART, stepped directly.
using ScenarioBoard = hal::HostBoard<AnyPlant>;
ScenarioBoard make_scenario_board(const Scenario& scenario, std::uint64_t seed);

/// The same firmware (same design) on the in-process host board with the same scenario and seed: the reference the
/// QEMU run must equal within float32 rounding. `design`: as HilOptions::design.
HilResult run_on_host_board(const std::string& scenario, std::uint64_t seed,
                            const std::optional<fw::RunDesign>& design = std::nullopt);
/// The same with the plant and the recording of `options` (plant_file, record); the QEMU fields are not used.
HilResult run_on_host_board(const HilOptions& options);

}  // namespace lashid::sim
