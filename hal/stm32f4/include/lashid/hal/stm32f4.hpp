// Board support for the STM32F405 (Cortex-M4F), on the chip and as QEMU 7.2 emulates it in the machine
// `netduinoplus2`; written from the STM32F4 reference manual RM0090 (rev 19), on top of hal/cortex_m (startup,
// SysTick, semihosting, stack). Heap-free, exception-free; polled but for the link's receive interrupt (USART1) and
// SysTick's wrap count.
//
//   start_clock_tree()  SYSCLK 168 MHz from the PLL on the HSE crystal (stm32f4/clock_tree.hpp, kClockPlan); on
//                       QEMU, whose RCC is a stub that reads 0, it keeps the emulator's fixed 168 MHz
//   Usart               USART1..6 (RM0090 30): its pins (stm32f4/usart_pins.hpp), RCC clock enable, BRR, CR1
//                       UE/TE/RE, polled SR TXE/RXNE, DR
//   Stm32f4Platform     the board-independent half of a hal::Board: link_write/link_read on USART1 (received by
//                       interrupt into cortex_m::link_rx_queue()), cycles(),
//                       wait_for_sample_tick() on SysTick; a firmware adds actuate()/measure()
//
// The crystal's frequency is the board's: LASHID_STM32F4_HSE_HZ (CMake cache, 8 MHz by default, as on ST's
// STM32F4DISCOVERY) and LASHID_STM32F4_HSE_BYPASS (an external clock instead of a crystal). docs/platform.md lists
// what else a real board needs.
#pragma once

#include <cstddef>
#include <cstdint>

#include "lashid/hal/cortex_m.hpp"
#include "lashid/hal/status.hpp"
#include "lashid/hal/stm32f4/clock_tree.hpp"
#include "lashid/hal/stm32f4/register_bus.hpp"
#include "lashid/hal/stm32f4/usart_pins.hpp"

#ifndef LASHID_STM32F4_HSE_HZ
#define LASHID_STM32F4_HSE_HZ 8000000
#endif
#ifndef LASHID_STM32F4_HSE_BYPASS
#define LASHID_STM32F4_HSE_BYPASS 0
#endif

namespace lashid::hal::stm32f4 {

// ---- Platform constants ---------------------------------------------------------------------------------------------

/// The board's clock tree: 168 MHz (the STM32F405's maximum, RM0090 7.2) from its crystal; APB1 42 MHz, APB2 84 MHz.
inline constexpr ClockPlan kClockPlan = plan_for_hse(LASHID_STM32F4_HSE_HZ, LASHID_STM32F4_HSE_BYPASS != 0);
static_assert(kClockPlan.valid(),
              "LASHID_STM32F4_HSE_HZ: the crystal must be a whole number of MHz in 4-26 MHz (1-50 MHz bypassed), "
              "or choose the PLL's M and N by hand (RM0090 7.3.2)");
/// SYSCLK = HCLK: the CPU clock and SysTick's processor clock. QEMU's netduinoplus2 runs at the same 168 MHz
/// (SYSCLK_FRQ), fixed.
inline constexpr std::uint32_t kSystemClockHz = kClockPlan.hclk_hz();
static_assert(kSystemClockHz == 168'000'000, "QEMU netduinoplus2 runs at 168 MHz: the plan must give the same");
inline constexpr std::uint32_t kApb1ClockHz = kClockPlan.pclk1_hz();  ///< PCLK1 (USART2/3, UART4/5), 42 MHz maximum
inline constexpr std::uint32_t kApb2ClockHz = kClockPlan.pclk2_hz();  ///< PCLK2 (USART1/6), 84 MHz maximum
inline constexpr std::uint32_t kDefaultBaud = 115'200;
/// Under `-icount shift=0` one guest instruction is 1 ns, and one 168 MHz cycle 5.952 ns: 125 / 21 instructions per
/// cycle (not an integer, unlike mps2's 40). lashid hil --ticks-to-instructions takes the ratio as a decimal.
inline constexpr std::uint32_t kIcount0InstructionsPerCycleNum = 125;
inline constexpr std::uint32_t kIcount0InstructionsPerCycleDen = 21;
static_assert(std::uint64_t{kSystemClockHz} * kIcount0InstructionsPerCycleNum ==
                  std::uint64_t{1'000'000'000U} * kIcount0InstructionsPerCycleDen,
              "1 ns per instruction at 168 MHz");

/// A USART: its registers and the RCC bit that clocks it (RM0090 2.3 memory map, 7.3.13/7.3.14 APBxENR).
struct UsartPort {
  std::uintptr_t base;
  std::uintptr_t rcc_enable_register;  ///< RCC_APB1ENR or RCC_APB2ENR
  std::uint32_t rcc_enable_bit;
  std::uint32_t pclk_hz;               ///< the APB clock its baud rate generator divides
  UsartPins pins;                      ///< its TX and RX pins
  std::uint32_t irq;                   ///< its interrupt line (RM0090 Table 61)
};
inline constexpr std::uintptr_t kRccBase = 0x4002'3800;                        ///< RM0090 2.3, Table 1
/// USART1's interrupt line (RM0090 Table 61, position 37): the link's receive interrupt.
inline constexpr std::uint32_t kUsart1Irq = 37;
/// USART2's interrupt line (RM0090 Table 61, position 38): the plant port's receive wake-up.
inline constexpr std::uint32_t kUsart2Irq = 38;
/// APB2ENR.USART1EN; PA9/PA10.
inline constexpr UsartPort kUsart1{0x4001'1000, kRccBase + 0x44, 1U << 4, kApb2ClockHz, kUsart1PinsPA9PA10,
                                    kUsart1Irq};
/// APB1ENR.USART2EN; PA2/PA3.
inline constexpr UsartPort kUsart2{0x4000'4400, kRccBase + 0x40, 1U << 17, kApb1ClockHz, kUsart2PinsPA2PA3,
                                    kUsart2Irq};

/// The link's transmitter through a queue that USART1's interrupt drains (on TXE), for an image whose sample loop
/// must not wait for the wire (hal::BuffersLinkWrites: the analog image streams its samples). Queues all `size`
/// bytes, never part of them (a frame is not split), once there is room: kOk; kTimeout (no room within
/// kLinkTxWaitCycles: nothing queued); kLinkError (more bytes than the queue holds). Images that do not call it
/// transmit by polling (Usart::write) and link none of it.
inline constexpr std::size_t kLinkTxQueueBytes = 256;  // two full frames (126 bytes each)
inline constexpr std::uint32_t kLinkTxWaitCycles = kSystemClockHz / 10;  // 100 ms: 1,150 bytes at 115200 baud
Status queued_link_write(const std::uint8_t* data, std::size_t size);
/// Waits (at most kLinkTxWaitCycles) until every queued byte has left USART1's shift register (SR.TC): before the
/// image ends, so that its last reports are not cut. kOk or kTimeout.
Status drain_queued_link();

/// The board's clock tree (kClockPlan) on the chip's registers: call it first in main, before any peripheral, and
/// stop unless runs_as_planned(): every baud rate and sample period assumes kClockPlan's clocks.
ClockStart start_clock_tree();
/// What an identification image does first: start_clock_tree(), its outcome said on the console ("lashid: clocks:
/// <how>" or "lashid: clock tree not started: <why>"). The image then ends with kExitClockTree unless
/// runs_as_planned(): with other clocks every baud rate and sample period would be wrong, so nothing runs.
inline constexpr int kExitClockTree = 9;

// The core's half, under this board's namespace (as hal/mps2 does).
namespace semihosting = cortex_m::semihosting;
using cortex_m::core_name;
using cortex_m::cpu_part;
using cortex_m::expected_cpu_part;
using cortex_m::finish;
using cortex_m::fp_features;
using cortex_m::fpu_enabled;
using cortex_m::kBuiltWithFpu;
using cortex_m::machine_name;
using cortex_m::SampleTimer;
using cortex_m::stack_high_water_bytes;
using cortex_m::stack_size_bytes;
using cortex_m::SysTickClock;
using cortex_m::Text;

inline ClockStart start_clock_tree_and_say() {
  const ClockStart clock = start_clock_tree();
  semihosting::write(runs_as_planned(clock) ? "lashid: clocks: " : "lashid: clock tree not started: ");
  semihosting::write(to_string(clock));
  semihosting::write("\n");
  return clock;
}

// ---- USART ------------------------------------------------------------------------------------------------------------

class Usart {
 public:
  explicit constexpr Usart(const UsartPort& port = kUsart1) : port_(port) {}

  /// Routes its pins, clocks the USART (RCC), sets BRR for `baud` at its APB clock (16x oversampling, 8N1) and
  /// enables UE, TE, RE. QEMU ignores the pins, BRR and the RCC; the order is the one the hardware needs.
  void init(std::uint32_t baud = kDefaultBaud) const;
  /// Writes all bytes, waiting for TXE before each. kTimeout if TXE stays clear for ~1e6 polls.
  Status write(const std::uint8_t* data, std::size_t size) const;
  Status write(const char* text) const;
  /// Non-blocking read of one byte: kOk; kWouldBlock (RXNE clear); kLinkError (overrun, framing or noise error: the
  /// error is cleared by the SR-then-DR read sequence of RM0090 30.6.1, which also drops the byte in DR).
  Status read(std::uint8_t& byte) const;
  /// Whether read() has something to say (a byte or an error): it would not return kWouldBlock.
  bool rx_pending() const;
  /// The receive interrupt for one wake-up: arm_rx_wake() sets RXNEIE and enables the line in the NVIC (its stale
  /// pending state cleared), and the interrupt handler calls disarm_rx_wake(), which disables the line in the NVIC.
  /// The byte stays in DR for read(). (Clearing RXNEIE would not do: QEMU's USART lowers its line only when DR is
  /// read.)
  void arm_rx_wake() const;
  void disarm_rx_wake() const;

 private:
  UsartPort port_;
};

// ---- The platform half of a hal::Board --------------------------------------------------------------------------------

/// USART1 as the byte link (received by interrupt), SysTick as the clock and the sample tick (as Mps2Platform on
/// mps2).
class Stm32f4Platform {
 public:
  constexpr Stm32f4Platform() = default;

  /// Initialises USART1 with its receive interrupt (bytes go to cortex_m::link_rx_queue()) and starts SysTick; the
  /// first sample tick is `sample_period_cycles` later.
  void init(std::uint32_t sample_period_cycles, std::uint32_t baud = kDefaultBaud);

  Status link_write(const std::uint8_t* data, std::size_t size) { return usart_.write(data, size); }
  /// From the receive queue: kOk; kWouldBlock; kLinkError once after bytes were lost (overrun, framing or noise
  /// error, or a full queue).
  Status link_read(std::uint8_t& byte);
  Status wait_for_sample_tick() { return timer_.wait(); }
  std::uint32_t cycles() const { return SysTickClock::cycles(); }

  const Usart& usart() const { return usart_; }
  const SampleTimer& sample_timer() const { return timer_; }

 private:
  Usart usart_{kUsart1};
  SampleTimer timer_;
};

}  // namespace lashid::hal::stm32f4
