// The link's queued transmitter (stm32f4.hpp, queued_link_write): the main loop queues whole frames, USART1's
// interrupt (LinkRx_IRQHandler in board.cpp, which serves both directions) moves one byte per TXE into DR, and
// switches its TXE interrupt off once the queue is empty. Linked only into an image that calls queued_link_write;
// it then replaces board.cpp's weak lashid_link_tx_interrupt.
//
// CR1 is changed by both sides: the main loop sets TXEIE after queueing, the interrupt clears it when the queue is
// empty. The interrupt runs to completion between the main loop's instructions, so its "empty, clear TXEIE" is
// atomic to the main loop; the main loop's read-modify-write of CR1 can be interrupted, and then writes back
// TXEIE = 1 over a clear: one extra interrupt that finds the queue empty and clears it again. No other bit of CR1
// is changed by the interrupt.
//
// The main loop also moves bytes itself while TXE is set (pump(), with interrupts masked, so that the queue keeps one
// consumer at a time): on the chip TXE is set for one or two bytes at a time (the data register and an idle shift
// register), so it sends at most those and the interrupt does the rest; QEMU 7.2's USART, whose TXE is always set
// and which raises its interrupt for RXNE only (later QEMUs also for TXE), is drained there.
#include "lashid/hal/isr_byte_queue.hpp"
#include "lashid/hal/stm32f4.hpp"
#include "registers.hpp"

namespace lashid::hal::stm32f4 {

namespace {

IsrByteQueue<kLinkTxQueueBytes> g_link_tx;

constexpr std::uintptr_t kCr1 = kUsart1.base + detail::kUsartCr1;
constexpr std::uintptr_t kSr = kUsart1.base + detail::kUsartSr;

// The next queued byte into DR while TXE is set; TXEIE off once the queue is empty. The caller masks interrupts
// (or is the interrupt).
void send_while_ready() {
  using namespace detail;
  std::uint8_t byte = 0;
  while ((reg(kSr) & kSrTxe) != 0U) {
    const auto taken = g_link_tx.take(byte);
    if (taken == IsrByteQueue<kLinkTxQueueBytes>::Take::kEmpty) {
      reg(kCr1) = reg(kCr1) & ~kCr1Txeie;
      return;
    }
    // kLost cannot happen (the producer checks room() first): reported once, the byte follows.
    if (taken == IsrByteQueue<kLinkTxQueueBytes>::Take::kByte) reg(kUsart1.base + kUsartDr) = byte;
  }
}

// The main loop's share of the work (see the top of the file), with interrupts masked (PRIMASK kept).
void pump() {
  std::uint32_t primask = 0;
  __asm__ volatile("mrs %0, primask\n\tcpsid i" : "=r"(primask)::"memory");
  send_while_ready();
  __asm__ volatile("msr primask, %0" ::"r"(primask) : "memory");
}

}  // namespace

Status queued_link_write(const std::uint8_t* data, std::size_t size) {
  using namespace detail;
  if (size > kLinkTxQueueBytes) return Status::kLinkError;
  const std::uint32_t start = SysTickClock::cycles();
  while (g_link_tx.room() < size) {
    pump();
    if (SysTickClock::cycles() - start > kLinkTxWaitCycles) return Status::kTimeout;
  }
  for (std::size_t i = 0; i < size; ++i) (void)g_link_tx.push(data[i]);  // room() was enough: no loss
  reg(kCr1) = reg(kCr1) | kCr1Txeie;
  pump();
  return Status::kOk;
}

Status drain_queued_link() {
  using namespace detail;
  const std::uint32_t start = SysTickClock::cycles();
  while (g_link_tx.size() != 0U || (reg(kSr) & kSrTc) == 0U) {
    pump();
    if (SysTickClock::cycles() - start > kLinkTxWaitCycles) return Status::kTimeout;
  }
  return Status::kOk;
}

}  // namespace lashid::hal::stm32f4

// USART1's TXE with TXEIE set: the next queued bytes into DR while it takes them, TXEIE off when there are none.
extern "C" void lashid_link_tx_interrupt() { lashid::hal::stm32f4::send_while_ready(); }
