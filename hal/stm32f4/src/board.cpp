// The STM32F405 facts the shared Cortex-M support asks of its board (lashid/hal/cortex_m.hpp), and the platform's
// init.
#include "lashid/hal/stm32f4.hpp"
#include "registers.hpp"

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

static_assert(kUsart1Irq == LASHID_LINK_RX_IRQ, "the vector table's link interrupt must be USART1's");
static_assert(kUsart2Irq == LASHID_PLANT_RX_IRQ, "the vector table's plant port interrupt must be USART2's");

void Stm32f4Platform::init(std::uint32_t sample_period_cycles, std::uint32_t baud) {
  usart_.init(baud);
  // Received bytes now go through LinkRx_IRQHandler into the queue (lashid/hal/cortex_m.hpp).
  detail::reg(kUsart1.base + detail::kUsartCr1) = detail::reg(kUsart1.base + detail::kUsartCr1) | detail::kCr1Rxneie;
  cortex_m::enable_irq(kUsart1Irq);
  // A zero event every sample period: the sample tick and a plant port's answer are waited for asleep, and these
  // events bound every such sleep (SampleTimer::wait, RemoteIdentificationBoard's UartChannel::idle).
  SysTickClock::start(sample_period_cycles - 1U);
  timer_.start(sample_period_cycles);
}

Status Stm32f4Platform::link_read(std::uint8_t& byte) { return cortex_m::read_link_rx(byte); }

}  // namespace lashid::hal::stm32f4

// The transmit half of USART1's interrupt when no queued transmitter is linked (queued_link_tx.cpp replaces it): TXEIE
// is never set then; should it be, it is cleared, so that the interrupt does not fire forever.
extern "C" __attribute__((weak)) void lashid_link_tx_interrupt() {
  using namespace lashid::hal::stm32f4::detail;
  constexpr std::uintptr_t cr1 = lashid::hal::stm32f4::kUsart1.base + kUsartCr1;
  reg(cr1) = reg(cr1) & ~kCr1Txeie;
}

// USART1's interrupt (RM0090 Table 61, position 37), raised by RXNE or ORE with RXNEIE set, and by TXE with TXEIE set
// (an image with the queued transmitter, lashid_link_tx_interrupt). Reading SR then DR clears
// RXNE and the error flags (30.6.1). On an overrun DR still holds the last good byte (the later ones are lost): it is
// kept, and the loss marked after it. A byte with a framing, noise or parity error is itself damaged: dropped, and
// marked as lost.
extern "C" void LinkRx_IRQHandler() {
  using namespace lashid::hal::stm32f4::detail;
  constexpr std::uintptr_t base = lashid::hal::stm32f4::kUsart1.base;
  lashid::hal::cortex_m::LinkRxQueue& queue = lashid::hal::cortex_m::link_rx_queue();
  const std::uint32_t sr = reg(base + kUsartSr);
  if ((sr & kSrTxe) != 0U && (reg(base + kUsartCr1) & kCr1Txeie) != 0U) lashid_link_tx_interrupt();
  if ((sr & (kSrRxne | kSrRxErrors)) == 0U) return;
  const auto byte = static_cast<std::uint8_t>(reg(base + kUsartDr) & 0xFFU);
  if ((sr & (kSrFe | kSrNf | kSrPe)) != 0U) {
    queue.note_lost();
    return;
  }
  (void)queue.push(byte);
  if ((sr & kSrOre) != 0U) queue.note_lost();
}
