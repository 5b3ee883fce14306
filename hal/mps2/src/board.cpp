// The mps2 facts the shared Cortex-M support asks of its board (lashid/hal/cortex_m.hpp), and the platform's init.
#include "lashid/hal/mps2.hpp"

// The machine, for `lashid hil` (section .lashid.machine, not loaded).
LASHID_CORTEX_M_MACHINE_TAG(LASHID_QEMU_MACHINE_NAME);

namespace lashid::hal::cortex_m {

const char* machine_name() { return LASHID_QEMU_MACHINE_NAME; }

std::uint32_t expected_cpu_part() { return LASHID_EXPECTED_CPU_PART; }

}  // namespace lashid::hal::cortex_m

namespace lashid::hal::mps2 {

void Mps2Platform::init(std::uint32_t sample_period_cycles, std::uint32_t baud) {
  uart_.init(baud);
  SysTickClock::start();
  timer_.start(sample_period_cycles);
}

}  // namespace lashid::hal::mps2
