#include "lashid/hil/hil.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>

#include "lashid/hil/qemu_args.hpp"
#include "lashid/sim/scenario.hpp"
#include "elf_image.hpp"
#include "played_run.hpp"
#include "qemu_process.hpp"
#include "session.hpp"
#include "stop_signals.hpp"

namespace lashid::sim {

std::vector<std::string> qemu_command_line(const QemuCommand& command) {
  std::vector<std::string> args{command.qemu, "-machine", command.machine};
  args.insert(args.end(), kQemuCommonArgs.begin(), kQemuCommonArgs.end());
  if (command.icount) args.insert(args.end(), kQemuIcountArgs.begin(), kQemuIcountArgs.end());
  for (const std::string& serial : command.serials) args.insert(args.end(), {"-serial", serial});
  args.insert(args.end(), {"-kernel", command.kernel});
  return args;
}

namespace {

// The preset that builds the image for each machine QEMU runs (CMakePresets.json), for the message below.
const char* preset_for(const std::string& machine) {
  if (machine == "mps2-an386") return "cm4f-release";
  if (machine == "mps2-an500") return "cm7-release";
  if (machine == "mps2-an385") return "cm3-release";
  if (machine == "netduinoplus2") return "stm32f405-release";
  return nullptr;
}

// An image whose plant is its own waits for a design on its link while nothing plays its plant port, and an image
// whose plant is played waits on a plant port nobody answers: both run into the time limit. Refused before QEMU starts.
void check_plant(const HilOptions& options) {
  const std::optional<std::string> plant = detail::elf_plant_tag(options.firmware);
  if (plant == "own" && !options.physical_plant) {
    throw std::runtime_error(fmt::format("hil: firmware '{}' drives its own actuator and sensor (an analog image): run "
                                         "it with --physical-plant and --config",
                                         options.firmware));
  }
  if (plant == "port" && options.physical_plant) {
    throw std::runtime_error(fmt::format("hil: firmware '{}' has its plant played over its plant port: "
                                         "--physical-plant needs an image with its own actuator and sensor (e.g. "
                                         "lashid_fw_analog.elf of preset stm32f405-release)",
                                         options.firmware));
  }
}

}  // namespace

void check_firmware_image(const std::string& firmware, const std::string& machine, std::string_view command) {
  if (!std::filesystem::is_regular_file(firmware)) {
    throw std::runtime_error(fmt::format("{}: firmware '{}' not found", command, firmware));
  }
  if (!detail::is_arm_elf(firmware)) {
    // QEMU would boot any bytes and stop in a lockup with a register dump.
    throw std::runtime_error(fmt::format("{}: firmware '{}' is not an ARM ELF image (a cross preset builds one: "
                                         "build/cm4f-release/firmware/lashid_fw.elf)",
                                         command, firmware));
  }
  if (const std::optional<std::string> damage = detail::elf_damage(firmware)) {
    throw std::runtime_error(fmt::format("{}: firmware '{}' is damaged: {}", command, firmware, *damage));
  }
  // An image built for another machine faults or waits on a UART that is not there, until the time limit: refused
  // before QEMU starts, naming both machines.
  const std::optional<std::string> built_for = detail::elf_machine_tag(firmware);
  if (!built_for || *built_for == machine) return;
  const char* preset = preset_for(machine);
  throw std::runtime_error(
      fmt::format("{}: firmware '{}' is built for QEMU machine '{}', not '{}': run it with --machine {}{}", command,
                  firmware, *built_for, machine, *built_for,
                  preset != nullptr ? fmt::format(", or build the image for {} (preset {})", machine, preset) : ""));
}

HilResult run_hil(const HilOptions& options) {
  const bool attach = !options.attach_link.empty() || !options.attach_plant.empty();
  if (options.physical_plant && !options.attach_plant.empty()) {
    throw std::runtime_error("hil: a physical plant has no plant port to attach: give the link only");
  }
  if (attach && (options.attach_link.empty() || (options.attach_plant.empty() && !options.physical_plant))) {
    throw std::runtime_error("hil: attaching needs both sockets (link = UART0, plant = UART1)");
  }
  if (!attach) {
    check_firmware_image(options.firmware, options.machine, "hil");
    check_plant(options);
  }
  // The design sent (options.design or the scenario's), the plant played (the scenario's or a plant file's) and
  // the recording, opened before QEMU starts (played_run.hpp).
  const fw::RunDesign design = detail::run_design_of(options);
  AnyPlant plant = detail::played_plant(options, design);
  std::optional<RunRecorder> recorder;
  detail::start_recording(recorder, options, design);
  // From here on a stop signal ends the run through the cleanup below (stop_signals.hpp).
  const detail::StopSignals stop_signals;
  // The sockets' folder in $TMPDIR (else /tmp), removed by the cleanup.
  std::string dir_template = (std::filesystem::temp_directory_path() / "lashid-hil-XXXXXX").string();
  if (::mkdtemp(dir_template.data()) == nullptr) detail::fail_errno("mkdtemp in " + dir_template);
  const std::filesystem::path dir(dir_template);
  HilResult result;
  pid_t qemu = -1;
  detail::SessionFds fds;
  const auto cleanup = [&] {
    for (int fd : {fds.link, fds.plant, fds.console}) {
      if (fd >= 0) ::close(fd);
    }
    fds = {};
    if (qemu > 0 && ::waitpid(qemu, nullptr, WNOHANG) == 0) {
      ::kill(qemu, SIGKILL);
      ::waitpid(qemu, nullptr, 0);
    }
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
  };
  try {
    if (attach) {
      // A socket that is not there yet may be a QEMU still starting: waited for, up to 10 s or --timeout.
      const int wait_ms = static_cast<int>(std::clamp(options.timeout_seconds * 1000.0, 1.0, 10000.0));
      fds.link = detail::connect_with_timeout(options.attach_link, wait_ms);
      if (!options.physical_plant) fds.plant = detail::connect_with_timeout(options.attach_plant, wait_ms);
    } else {
      detail::start_qemu(options, dir, qemu, fds);
    }
    detail::run_session(options, std::move(plant), recorder ? &*recorder : nullptr, design, qemu, fds, result);
  } catch (const std::exception& e) {
    cleanup();
    if (!recorder) throw;
    // A run that stops early keeps what it measured; the run's own error stays the one reported.
    std::string kept;
    try {
      detail::finish_recording(recorder, fmt::format("the host stopped the run: {}", e.what()), result);
      kept = result.recorded == 0
                 ? fmt::format("no recording written: not a sample was measured ({} keeps what it held)",
                               options.record)
                 : fmt::format("{} samples measured before it are in {} (marked partial)", result.recorded,
                               options.record);
    } catch (const std::exception& r) {
      kept = fmt::format("no recording written: {}", r.what());
    }
    const std::string message = fmt::format("{}; {}", e.what(), kept);
    if (const auto* stopped = dynamic_cast<const HilInterrupted*>(&e)) throw HilInterrupted(message, stopped->signal());
    throw std::runtime_error(message);
  }
  cleanup();
  detail::finish_recording(recorder,
                           fmt::format("the firmware's run ended with {}, QEMU exit status {}",
                                       result.done < 0 ? std::string("no report")
                                                       : fmt::format("status '{}'", fw::to_string(
                                                                         static_cast<fw::RunStatus>(result.done))),
                                       result.qemu_exit),
                           result);
  return result;
}

}  // namespace lashid::sim
