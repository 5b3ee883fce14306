// Board support for QEMU's ARM MPS2 machines: mps2-an385 (Cortex-M3), mps2-an386 (Cortex-M4F), mps2-an500
// (Cortex-M7F). Heap-free, exception-free, polled (the only interrupt used is SysTick's wrap count).
//
//   Mps2Uart            CMSDK APB UART (UART0 is the byte link and console): init, write, non-blocking read, errors
//   SysTickClock        SysTick's 24-bit down counter extended to a 32-bit monotonic count of CPU clock cycles
//   SampleTimer         a fixed sample period on SysTickClock (the sample tick of hal::Board)
//   Mps2Platform        the board-independent half of a hal::Board: link_write/link_read on UART0, cycles(),
//                       wait_for_sample_tick(); a firmware adds actuate()/measure() (e.g. over the link)
//   semihosting::       console output and the exit code to QEMU (-semihosting-config enable=on)
//   stack_*()           the stack is painted at reset; the high-water mark is measured by scanning the paint
//   finish(code)        prints the stack report and exits QEMU with `code` (what returning from main() does)
//
// Facts from QEMU 7.2 hw/arm/mps2.c (checked with `info mtree` / `info qtree`, see docs/firmware-platform.md):
// UART0 at 0x40004000; SYSCLK (CPU clock, SysTick's processor clock, UART PCLK) 25 MHz; SysTick reference clock
// 1 MHz. Under `-icount shift=0` one guest instruction is 1 ns of virtual time, so one SysTick cycle (40 ns) is
// 40 instructions: see kInstructionsPerCycleIcount0.
#pragma once

#include <cstddef>
#include <cstdint>

#include "lashid/hal/status.hpp"

namespace lashid::hal::mps2 {

// ---- Platform constants ---------------------------------------------------------------------------------------------

inline constexpr std::uint32_t kSystemClockHz = 25'000'000;     ///< SYSCLK of the mps2 machines (QEMU: SYSCLK_FRQ)
inline constexpr std::uint32_t kSysTickRefClockHz = 1'000'000;  ///< SysTick external reference clock (unused)
inline constexpr std::uintptr_t kUart0Base = 0x4000'4000;       ///< CMSDK APB UART0 on AN385/AN386/AN500
inline constexpr std::uint32_t kDefaultBaud = 115'200;
/// Guest instructions per SysTick cycle when QEMU runs with `-icount shift=0` (1 instruction = 1 ns of virtual
/// time, one 25 MHz cycle = 40 ns). Only meaningful under that option; without -icount, SysTick follows host time.
inline constexpr std::uint32_t kInstructionsPerCycleIcount0 = 1'000'000'000U / kSystemClockHz;
static_assert(kInstructionsPerCycleIcount0 * kSystemClockHz == 1'000'000'000U, "40 ns per cycle exactly");

/// The QEMU machine the image was linked for ("mps2-an386", ...), and the core the compiler targeted.
const char* machine_name();
const char* core_name();
/// CPUID.PartNo expected on the machine the image was linked for (0xC23 Cortex-M3, 0xC24 M4, 0xC27 M7) and the
/// one the CPU reports: they differ when an image runs on the wrong -machine.
std::uint32_t expected_cpu_part();
std::uint32_t cpu_part();
/// Whether the image was built for an FPU (hard-float), and if so whether CPACR grants CP10/CP11 full access now.
inline constexpr bool kBuiltWithFpu =
#if defined(__ARM_FP)
    true;
#else
    false;
#endif
bool fpu_enabled();
/// MVFR0 (FP feature register 0), 0 on cores without an FPU. Bits [7:4] single, [11:8] double precision.
std::uint32_t fp_features();

// ---- Semihosting (ARM semihosting v2 over `bkpt 0xAB`; QEMU: -semihosting-config enable=on,target=native) --------

namespace semihosting {
/// SYS_WRITE0: a NUL-terminated string to the debugger console (QEMU: its stderr).
void write(const char* text);
/// SYS_WRITEC: one character.
void write_char(char c);
/// SYS_EXIT (code 0) or SYS_EXIT_EXTENDED (any other code): QEMU exits with `code` (0..255). Never returns.
[[noreturn]] void exit(int code);
}  // namespace semihosting

/// Exit codes the platform itself uses (a firmware's main() may return any other).
inline constexpr int kExitAbort = 134;           ///< abort(), failed assert(), pure virtual call
inline constexpr int kExitHardFault = 135;       ///< HardFault (incl. escalated UsageFault/BusFault/MemManage)
inline constexpr int kExitUnexpectedIrq = 136;   ///< an exception or interrupt without a handler
inline constexpr int kExitStackOverflow = 137;   ///< finish(): the stack paint was used up entirely

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
  /// The sticky error flags, and clearing them.
  Errors errors() const;
  void clear_errors() const;

 private:
  std::uintptr_t base_;
};

// ---- SysTick ----------------------------------------------------------------------------------------------------------

class SysTickClock {
 public:
  static constexpr std::uint32_t kMaxReload = 0x00FF'FFFF;  ///< the counter is 24 bits wide

  /// Starts SysTick on the processor clock with RELOAD = `reload` (period reload + 1 cycles) and its wrap interrupt,
  /// and restarts cycles() from 0. Interrupts must not stay masked for longer than one period (2^24 cycles = 671 ms
  /// at the default), or wraps are lost.
  static void start(std::uint32_t reload = kMaxReload);
  static void stop();
  /// CPU clock cycles since start(), modulo 2^32 (differences are valid across one wrap: 171.8 s at 25 MHz).
  /// Monotonic also when called with interrupts masked (a pending wrap is accounted for).
  static std::uint32_t cycles();
  /// SysTick wraps counted so far (the interrupt count, for tests).
  static std::uint32_t wraps();
};

/// A fixed sample period on SysTickClock: wait() returns at start + k * period.
class SampleTimer {
 public:
  /// The first wait() returns `period_cycles` after this call.
  void start(std::uint32_t period_cycles);
  /// kOk at the next sample instant; kTimeout at once when that instant has already passed (the previous sample
  /// overran its period): the sample is late, not skipped, and the schedule restarts from now.
  Status wait();
  std::uint32_t period() const { return period_; }
  std::uint32_t overruns() const { return overruns_; }

 private:
  std::uint32_t period_ = 0;
  std::uint32_t next_ = 0;
  std::uint32_t overruns_ = 0;
};

// ---- The platform half of a hal::Board --------------------------------------------------------------------------------

/// UART0 as the byte link, SysTick as the clock and the sample tick. A board type for the firmware composes this with
/// its actuate()/measure(); together they satisfy lashid::hal::Board (see firmware/smoke/main.cpp).
class Mps2Platform {
 public:
  explicit constexpr Mps2Platform(std::uintptr_t uart_base = kUart0Base) : uart_(uart_base) {}

  /// Initialises the UART and starts SysTick; the first sample tick is `sample_period_cycles` later.
  void init(std::uint32_t sample_period_cycles, std::uint32_t baud = kDefaultBaud);

  Status link_write(const std::uint8_t* data, std::size_t size) { return uart_.write(data, size); }
  Status link_read(std::uint8_t& byte) { return uart_.read(byte); }
  Status wait_for_sample_tick() { return timer_.wait(); }
  std::uint32_t cycles() const { return SysTickClock::cycles(); }

  const Mps2Uart& uart() const { return uart_; }
  const SampleTimer& sample_timer() const { return timer_; }

 private:
  Mps2Uart uart_;
  SampleTimer timer_;
};

// ---- Stack --------------------------------------------------------------------------------------------------------------

/// The word the reset handler paints the whole stack with before anything runs on it.
inline constexpr std::uint32_t kStackPaint = 0x5AC5'5AC5U;
/// Size of the stack region (linker script: __stack_size, default 16 KiB).
std::size_t stack_size_bytes();
/// Deepest stack use since reset, in bytes: the stack region minus the still-painted words at its bottom. Equal to
/// stack_size_bytes() when the paint is gone entirely (the stack overflowed, or came within one word of it).
std::size_t stack_high_water_bytes();

/// Prints "lashid: exit <code>, stack high-water <n> of <size> bytes" on the semihosting console and exits QEMU with
/// `code` (kExitStackOverflow instead of 0 when the stack paint is used up). Returning from main() calls this.
[[noreturn]] void finish(int code);

// ---- Heap-free text -------------------------------------------------------------------------------------------------

/// A fixed-capacity, NUL-terminated text buffer for messages (no printf: stdio would pull in the heap).
/// Appends that do not fit are truncated.
template <std::size_t Capacity>
class Text {
  static_assert(Capacity >= 2);

 public:
  Text() { data_[0] = '\0'; }
  const char* c_str() const { return data_; }
  std::size_t size() const { return size_; }
  void clear() {
    size_ = 0;
    data_[0] = '\0';
  }

  Text& operator<<(const char* s) {
    while (*s != '\0') put(*s++);
    return *this;
  }
  Text& operator<<(char c) {
    put(c);
    return *this;
  }
  Text& operator<<(std::uint32_t v) {
    char digits[10];
    int n = 0;
    do {
      digits[n++] = static_cast<char>('0' + v % 10U);
      v /= 10U;
    } while (v != 0U);
    while (n > 0) put(digits[--n]);
    return *this;
  }
  Text& operator<<(std::int32_t v) {
    if (v < 0) {
      put('-');
      return *this << (0U - static_cast<std::uint32_t>(v));  // unsigned: |INT32_MIN| without overflow
    }
    return *this << static_cast<std::uint32_t>(v);
  }
  Text& operator<<(std::uint64_t v) {
    char digits[20];
    int n = 0;
    do {
      digits[n++] = static_cast<char>('0' + static_cast<int>(v % 10U));
      v /= 10U;
    } while (v != 0U);
    while (n > 0) put(digits[--n]);
    return *this;
  }
  /// 0x-prefixed, `width` hex digits.
  Text& hex(std::uint32_t v, int width = 8) {
    *this << "0x";
    for (int shift = 4 * (width - 1); shift >= 0; shift -= 4) {
      put("0123456789abcdef"[(v >> static_cast<unsigned>(shift)) & 0xFU]);
    }
    return *this;
  }
  /// Fixed-point with `decimals` digits (|x| < 2^31 / 10^decimals; non-finite prints as "nan"/"inf").
  Text& fixed(float x, int decimals = 6) {
    if (x != x) return *this << "nan";
    if (x < 0.0f) {
      put('-');
      x = -x;
    }
    if (x > 2.0e9f) return *this << "inf";
    std::uint32_t scale = 1;
    for (int i = 0; i < decimals; ++i) scale *= 10U;
    const auto whole = static_cast<std::uint32_t>(x);
    auto frac = static_cast<std::uint32_t>((x - static_cast<float>(whole)) * static_cast<float>(scale) + 0.5f);
    std::uint32_t w = whole;
    if (frac >= scale) {
      frac -= scale;
      ++w;
    }
    *this << w;
    if (decimals > 0) {
      put('.');
      for (std::uint32_t d = scale / 10U; d > 0U; d /= 10U) put(static_cast<char>('0' + (frac / d) % 10U));
    }
    return *this;
  }

 private:
  void put(char c) {
    if (size_ + 1 < Capacity) {
      data_[size_++] = c;
      data_[size_] = '\0';
    }
  }

  char data_[Capacity];
  std::size_t size_ = 0;
};

}  // namespace lashid::hal::mps2
