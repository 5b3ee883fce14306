// Board support for the STM32F405 (Cortex-M4F), as QEMU 7.2 emulates it in the machine `netduinoplus2`; written from
// the STM32F4 reference manual RM0090 (rev 19), on top of hal/cortex_m (startup, SysTick, semihosting, stack).
// Heap-free, exception-free, polled (the only interrupt used is SysTick's wrap count).
//
//   Usart               USART1..6 (RM0090 30): RCC clock enable, BRR, CR1 UE/TE/RE, polled SR TXE/RXNE, DR
//   Stm32f4Platform     the board-independent half of a hal::Board: link_write/link_read on USART1, cycles(),
//                       wait_for_sample_tick() on SysTick; a firmware adds actuate()/measure()
//
// The clock tree is taken as QEMU presents it: SYSCLK = HCLK = 168 MHz, fixed (QEMU's RCC is an unimplemented-device
// stub: writes are ignored, reads return 0, so waiting for PLLRDY would hang). A real board must first start the HSE
// and the PLL and set the flash wait states (RM0090 6.3.2, 3.5.1); the baud rate divisors below assume the usual
// APB prescalers at 168 MHz (APB1 42 MHz, APB2 84 MHz). docs/platform.md lists what else a real board needs.
#pragma once

#include <cstddef>
#include <cstdint>

#include "lashid/hal/cortex_m.hpp"
#include "lashid/hal/status.hpp"

namespace lashid::hal::stm32f4 {

// ---- Platform constants ---------------------------------------------------------------------------------------------

/// SYSCLK = HCLK: the CPU clock and SysTick's processor clock (QEMU netduinoplus2: SYSCLK_FRQ, 168 MHz, the
/// STM32F405's maximum, RM0090 6.2).
inline constexpr std::uint32_t kSystemClockHz = 168'000'000;
inline constexpr std::uint32_t kApb1ClockHz = kSystemClockHz / 4;  ///< PCLK1 (USART2/3, UART4/5), 42 MHz maximum
inline constexpr std::uint32_t kApb2ClockHz = kSystemClockHz / 2;  ///< PCLK2 (USART1/6), 84 MHz maximum
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
};
inline constexpr std::uintptr_t kRccBase = 0x4002'3800;                        ///< RM0090 2.3, Table 1
inline constexpr UsartPort kUsart1{0x4001'1000, kRccBase + 0x44, 1U << 4, kApb2ClockHz};   ///< APB2ENR.USART1EN
inline constexpr UsartPort kUsart2{0x4000'4400, kRccBase + 0x40, 1U << 17, kApb1ClockHz};  ///< APB1ENR.USART2EN

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

// ---- USART ------------------------------------------------------------------------------------------------------------

class Usart {
 public:
  explicit constexpr Usart(const UsartPort& port = kUsart1) : port_(port) {}

  /// Clocks the USART (RCC), sets BRR for `baud` at its APB clock (16x oversampling, 8N1) and enables UE, TE, RE.
  /// QEMU ignores BRR and the RCC; the order is the one the hardware needs.
  void init(std::uint32_t baud = kDefaultBaud) const;
  /// Writes all bytes, waiting for TXE before each. kTimeout if TXE stays clear for ~1e6 polls.
  Status write(const std::uint8_t* data, std::size_t size) const;
  Status write(const char* text) const;
  /// Non-blocking read of one byte: kOk; kWouldBlock (RXNE clear); kLinkError (overrun, framing or noise error: the
  /// error is cleared by the SR-then-DR read sequence of RM0090 30.6.1, which also drops the byte in DR).
  Status read(std::uint8_t& byte) const;

 private:
  UsartPort port_;
};

// ---- The platform half of a hal::Board --------------------------------------------------------------------------------

/// USART1 as the byte link, SysTick as the clock and the sample tick (as Mps2Platform on mps2).
class Stm32f4Platform {
 public:
  explicit constexpr Stm32f4Platform(const UsartPort& link = kUsart1) : usart_(link) {}

  /// Initialises the USART and starts SysTick; the first sample tick is `sample_period_cycles` later.
  void init(std::uint32_t sample_period_cycles, std::uint32_t baud = kDefaultBaud);

  Status link_write(const std::uint8_t* data, std::size_t size) { return usart_.write(data, size); }
  Status link_read(std::uint8_t& byte) { return usart_.read(byte); }
  Status wait_for_sample_tick() { return timer_.wait(); }
  std::uint32_t cycles() const { return SysTickClock::cycles(); }

  const Usart& usart() const { return usart_; }
  const SampleTimer& sample_timer() const { return timer_; }

 private:
  Usart usart_;
  SampleTimer timer_;
};

}  // namespace lashid::hal::stm32f4
