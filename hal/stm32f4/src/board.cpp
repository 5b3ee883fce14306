// The STM32F405 facts the shared Cortex-M support asks of its board (lashid/hal/cortex_m.hpp), and the platform's
// init.
#include "lashid/hal/stm32f4.hpp"

// The machine, for `lashid hil` (section .lashid.machine, not loaded).
LASHID_CORTEX_M_MACHINE_TAG(LASHID_QEMU_MACHINE_NAME);

namespace lashid::hal::cortex_m {

const char* machine_name() { return LASHID_QEMU_MACHINE_NAME; }

/// The STM32F405's core is a Cortex-M4 r0p1 (RM0090 38.6.1 / Cortex-M4 TRM: CPUID 0x410FC241, PartNo 0xC24).
std::uint32_t expected_cpu_part() { return 0xC24U; }

}  // namespace lashid::hal::cortex_m

namespace lashid::hal::stm32f4 {

ClockStart start_clock_tree() {
  // The register values at compile time: the image carries no division and no check of the plan.
  static constexpr ClockSettings kSettings = kClockPlan.settings();
  static_assert(kSettings.valid);
  MmioBus bus;
  return start_clock_tree(bus, kSettings);
}

void Stm32f4Platform::init(std::uint32_t sample_period_cycles, std::uint32_t baud) {
  usart_.init(baud);
  SysTickClock::start();
  timer_.start(sample_period_cycles);
}

}  // namespace lashid::hal::stm32f4
