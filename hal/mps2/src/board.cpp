// The mps2 facts the shared Cortex-M support asks of its board (lashid/hal/cortex_m.hpp), and the platform's init.
#include "lashid/hal/mps2.hpp"
#include "registers.hpp"

// The machine, for `lashid hil` (section .lashid.machine, not loaded).
LASHID_CORTEX_M_MACHINE_TAG(LASHID_QEMU_MACHINE_NAME);

namespace lashid::hal::cortex_m {

const char* machine_name() { return LASHID_QEMU_MACHINE_NAME; }

std::uint32_t expected_cpu_part() { return LASHID_EXPECTED_CPU_PART; }

}  // namespace lashid::hal::cortex_m

namespace lashid::hal::mps2 {

static_assert(kUart0RxIrq == LASHID_LINK_RX_IRQ, "the vector table's link interrupt must be UART0's receive");
static_assert(kUart1RxIrq == LASHID_PLANT_RX_IRQ, "the vector table's plant port interrupt must be UART1's receive");

void Mps2Platform::init(std::uint32_t sample_period_cycles, std::uint32_t baud) {
  uart_.init(baud);
  // Received bytes now go through LinkRx_IRQHandler into the queue (lashid/hal/cortex_m.hpp).
  detail::reg(kUart0Base + detail::kUartCtrl) = detail::reg(kUart0Base + detail::kUartCtrl) | detail::kUartRxIntEnable;
  cortex_m::enable_irq(kUart0RxIrq);
  // A byte that arrived between enabling RX and enabling its interrupt raised none (the CMSDK UART sets INTSTATUS.RX
  // only on arrival with RXINTEN on): QEMU would then hold every later byte back, a link that never speaks again.
  if ((detail::reg(kUart0Base + detail::kUartState) & detail::kUartRxFull) != 0U) cortex_m::pend_irq(kUart0RxIrq);
  // A zero event every sample period: the sample tick and a plant port's answer are waited for asleep, and these
  // events bound every such sleep (SampleTimer::wait, RemoteIdentificationBoard's UartChannel::idle).
  SysTickClock::start(sample_period_cycles - 1U);
  timer_.start(sample_period_cycles);
}

Status Mps2Platform::link_read(std::uint8_t& byte) { return cortex_m::read_link_rx(byte); }

}  // namespace lashid::hal::mps2

// UART0's receive interrupt (QEMU hw/arm/mps2.c: RX on line 0, TX on 1). The RX interrupt status is cleared before
// the data register is emptied: a byte that arrives in between raises it again instead of waiting unseen. On an
// overrun the byte held is the one before the loss: it is queued first, then the loss marked.
extern "C" void LinkRx_IRQHandler() {
  using namespace lashid::hal::mps2::detail;
  constexpr std::uintptr_t base = lashid::hal::mps2::kUart0Base;
  lashid::hal::cortex_m::LinkRxQueue& queue = lashid::hal::cortex_m::link_rx_queue();
  reg(base + kUartIntStatus) = kUartIntRx;
  for (std::uint32_t state = reg(base + kUartState); (state & (kUartRxFull | kUartRxOverrun)) != 0U;
       state = reg(base + kUartState)) {
    if ((state & kUartRxFull) != 0U) (void)queue.push(static_cast<std::uint8_t>(reg(base + kUartData) & 0xFFU));
    if ((state & kUartRxOverrun) != 0U) {
      reg(base + kUartState) = kUartRxOverrun;  // W1C
      queue.note_lost();
    }
  }
}
