// Private to the hil layer: the facts `lashid hil` reads from a firmware image before it boots it in QEMU.
#pragma once

#include <optional>
#include <string>

namespace lashid::sim::detail {

/// Whether `path` is a 32-bit little-endian ELF for ARM (e_machine EM_ARM): QEMU would boot any other bytes into a
/// lockup.
bool is_arm_elf(const std::string& path);

/// Why an ARM ELF image cannot be booted as it is (its program headers or a loaded segment, or its section table, lie
/// past the end of the file: a copy cut short), or std::nullopt when it is whole. QEMU would load what is there and
/// stop in a lockup, or boot an image whose tags cannot be read and wait on a UART until the time limit.
std::optional<std::string> elf_damage(const std::string& path);

/// The QEMU machine the image was built for: the NUL-terminated name in its section `.lashid.machine`
/// (LASHID_CORTEX_M_MACHINE_TAG, lashid/hal/cortex_m.hpp). std::nullopt when the image has no such section (an image
/// from elsewhere: it is run as it is) or its section table cannot be read.
std::optional<std::string> elf_machine_tag(const std::string& path);

/// Where the image's plant is: "port" (played over a plant-port UART) or "own" (the board's own actuator and sensor),
/// from its section `.lashid.plant` (LASHID_CORTEX_M_PLANT_TAG); std::nullopt as for the machine.
std::optional<std::string> elf_plant_tag(const std::string& path);

}  // namespace lashid::sim::detail
