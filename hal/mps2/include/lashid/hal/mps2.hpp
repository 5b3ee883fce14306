// Board support for QEMU's ARM MPS2 machines: mps2-an385 (Cortex-M3), mps2-an386 (Cortex-M4F), mps2-an500
// (Cortex-M7F). Heap-free, exception-free; polled but for the link's receive interrupt (UART0) and SysTick's wrap
// count.
//
//   Mps2Uart            CMSDK APB UART (UART0 is the byte link and console): init, write, non-blocking read, errors
//   Mps2Platform        the board-independent half of a hal::Board: link_write/link_read on UART0 (received by
//                       interrupt into cortex_m::link_rx_queue()), cycles(),
//                       wait_for_sample_tick(); a firmware adds actuate()/measure() (e.g. over the link)
//
// The core's half (SysTickClock, SampleTimer, semihosting, stack_*(), finish(), Text, startup, linker sections) is
// hal/cortex_m's (lashid/hal/cortex_m.hpp), shared with the STM32F4 board; its names are visible here as mps2::...
//
// Facts from QEMU 7.2 hw/arm/mps2.c (checked with `info mtree` / `info qtree`, see docs/firmware-platform.md):
// UART0 at 0x40004000; SYSCLK (CPU clock, SysTick's processor clock, UART PCLK) 25 MHz; SysTick reference clock
// 1 MHz. Under `-icount shift=0` one guest instruction is 1 ns of virtual time, so one SysTick cycle (40 ns) is
// 40 instructions: see kInstructionsPerCycleIcount0.
#pragma once

#include <cstddef>
#include <cstdint>

#include "lashid/hal/cortex_m.hpp"
#include "lashid/hal/status.hpp"

namespace lashid::hal::mps2 {

// ---- Platform constants ---------------------------------------------------------------------------------------------

inline constexpr std::uint32_t kSystemClockHz = 25'000'000;     ///< SYSCLK of the mps2 machines (QEMU: SYSCLK_FRQ)
inline constexpr std::uint32_t kSysTickRefClockHz = 1'000'000;  ///< SysTick external reference clock (unused)
inline constexpr std::uintptr_t kUart0Base = 0x4000'4000;       ///< CMSDK APB UART0 on AN385/AN386/AN500
inline constexpr std::uint32_t kUart0RxIrq = 0;  ///< its receive interrupt line (QEMU hw/arm/mps2.c: uartirq[0])
inline constexpr std::uintptr_t kUart1Base = 0x4000'5000;  ///< CMSDK APB UART1: the plant port (QEMU `info mtree`)
inline constexpr std::uint32_t kUart1RxIrq = 2;  ///< its receive interrupt line (QEMU hw/arm/mps2.c: uartirq[1])
inline constexpr std::uint32_t kDefaultBaud = 115'200;
/// Guest instructions per SysTick cycle when QEMU runs with `-icount shift=0` (1 instruction = 1 ns of virtual
/// time, one 25 MHz cycle = 40 ns). Only meaningful under that option; without -icount, SysTick follows host time.
inline constexpr std::uint32_t kInstructionsPerCycleIcount0 = 1'000'000'000U / kSystemClockHz;
static_assert(kInstructionsPerCycleIcount0 * kSystemClockHz == 1'000'000'000U, "40 ns per cycle exactly");

// The core's half, under the names the mps2 images have always used.
namespace semihosting = cortex_m::semihosting;
using cortex_m::core_name;
using cortex_m::cpu_part;
using cortex_m::expected_cpu_part;
using cortex_m::finish;
using cortex_m::fp_features;
using cortex_m::fpu_enabled;
using cortex_m::kBuiltWithFpu;
using cortex_m::kExitAbort;
using cortex_m::kExitHardFault;
using cortex_m::kExitStackOverflow;
using cortex_m::kExitUnexpectedIrq;
using cortex_m::kStackPaint;
using cortex_m::machine_name;
using cortex_m::SampleTimer;
using cortex_m::stack_high_water_bytes;
using cortex_m::stack_size_bytes;
using cortex_m::SysTickClock;
using cortex_m::Text;

// ---- CMSDK APB UART ---------------------------------------------------------------------------------------------------

class Mps2Uart {
 public:
  struct Errors {
    bool rx_overrun = false;  ///< a byte arrived while the previous one was unread: bytes were lost
    bool tx_overrun = false;  ///< a byte was written while the transmitter was full
  };

  explicit constexpr Mps2Uart(std::uintptr_t base = kUart0Base) : base_(base) {}

  /// Sets the baud divisor for `baud` at the 25 MHz PCLK and enables TX and RX (polled, no interrupts).
  void init(std::uint32_t baud = kDefaultBaud) const;
  /// Writes all bytes, waiting while the transmitter is full. kTimeout if it stays full for ~1e6 polls.
  Status write(const std::uint8_t* data, std::size_t size) const;
  Status write(const char* text) const;
  /// Non-blocking read of one byte: kOk; kWouldBlock (nothing pending); kLinkError (receive overrun since the last
  /// call: bytes were lost; the overrun is cleared and the byte now pending, if any, is left for the next call).
  Status read(std::uint8_t& byte) const;
  /// Whether read() has something to say (a byte or an overrun): it would not return kWouldBlock.
  bool rx_pending() const;
  /// The receive interrupt for one wake-up: arm_rx_wake() enables it, and the next byte's interrupt handler calls
  /// disarm_rx_wake(), which disables and clears it (the byte stays for read()).
  void arm_rx_wake() const;
  void disarm_rx_wake() const;
  /// The sticky error flags, and clearing them.
  Errors errors() const;
  void clear_errors() const;

 private:
  std::uintptr_t base_;
};

// ---- The platform half of a hal::Board --------------------------------------------------------------------------------

/// UART0 as the byte link (received by interrupt), SysTick as the clock and the sample tick. A board type for the firmware composes this with
/// its actuate()/measure(); together they satisfy lashid::hal::Board (see firmware/smoke/main.cpp).
class Mps2Platform {
 public:
  constexpr Mps2Platform() = default;

  /// Initialises UART0 with its receive interrupt (bytes go to cortex_m::link_rx_queue()) and starts SysTick; the
  /// first sample tick is `sample_period_cycles` later.
  void init(std::uint32_t sample_period_cycles, std::uint32_t baud = kDefaultBaud);

  Status link_write(const std::uint8_t* data, std::size_t size) { return uart_.write(data, size); }
  /// From the receive queue: kOk; kWouldBlock; kLinkError once after bytes were lost (UART overrun or a full queue).
  Status link_read(std::uint8_t& byte);
  Status wait_for_sample_tick() { return timer_.wait(); }
  std::uint32_t cycles() const { return SysTickClock::cycles(); }

  const Mps2Uart& uart() const { return uart_; }
  const SampleTimer& sample_timer() const { return timer_; }

 private:
  Mps2Uart uart_{kUart0Base};
  SampleTimer timer_;
};

}  // namespace lashid::hal::mps2
