// The link UART's receive queue and the NVIC enable (lashid/hal/cortex_m.hpp). The handler that fills the queue is
// the board's (LinkRx_IRQHandler: it knows its UART's registers); startup.cpp puts it at LASHID_LINK_RX_IRQ.
#include "lashid/hal/cortex_m.hpp"
#include "registers.hpp"

namespace lashid::hal::cortex_m {

namespace {
LinkRxQueue g_link_rx;  // zero-initialised (.bss): empty before any interrupt can fire
}  // namespace

LinkRxQueue& link_rx_queue() { return g_link_rx; }

void enable_irq(std::uint32_t irq) {
  // NVIC_ISER0..7 (ARMv7-M ARM B3.4.4): one write-1-to-set bit per line, 32 lines per register.
  detail::reg(detail::kNvicIser + 4U * (irq / 32U)) = 1U << (irq % 32U);
}

void disable_irq(std::uint32_t irq) {
  // NVIC_ICER0..7 (B3.4.5): write-1-to-clear enable.
  detail::reg(detail::kNvicIcer + 4U * (irq / 32U)) = 1U << (irq % 32U);
}

void clear_pending_irq(std::uint32_t irq) {
  // NVIC_ICPR0..7 (B3.4.7): write-1-to-clear pending.
  detail::reg(detail::kNvicIcpr + 4U * (irq / 32U)) = 1U << (irq % 32U);
}

void pend_irq(std::uint32_t irq) {
  // NVIC_ISPR0..7 (B3.4.6): write-1-to-set pending.
  detail::reg(detail::kNvicIspr + 4U * (irq / 32U)) = 1U << (irq % 32U);
}

Status read_link_rx(std::uint8_t& byte) {
  switch (g_link_rx.take(byte)) {
    case LinkRxQueue::Take::kByte: return Status::kOk;
    case LinkRxQueue::Take::kLost: return Status::kLinkError;
    case LinkRxQueue::Take::kEmpty: break;
  }
  return Status::kWouldBlock;
}

}  // namespace lashid::hal::cortex_m
