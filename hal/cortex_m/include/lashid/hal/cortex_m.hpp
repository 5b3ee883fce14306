// The Cortex-M (ARMv7-M / ARMv7E-M) half of every board support of the project, shared by hal/mps2 (QEMU's mps2
// machines) and hal/stm32f4 (STM32F405, QEMU netduinoplus2): nothing here depends on a vendor's peripherals.
// Heap-free, exception-free. Two interrupts: SysTick's wrap count and the link UART's receive (LinkRx_IRQHandler,
// the board's); every other I/O is polled.
//
//   link_rx_queue()     the link UART's received bytes, put there by its receive interrupt (the board's handler)
//   SysTickClock        SysTick's 24-bit down counter extended to a 32-bit monotonic count of CPU clock cycles
//   SampleTimer         a fixed sample period on SysTickClock (the sample tick of hal::Board)
//   semihosting::       console output and the exit code to QEMU (-semihosting-config enable=on)
//   stack_*()           the stack is painted at reset; the high-water mark is measured by scanning the paint
//   finish(code)        prints the stack report and exits QEMU with `code` (what returning from main() does)
//   Text                heap-free message formatting
//
// The startup (hal/cortex_m/src/startup.cpp: vector table, reset with the FPU enabled before any float code, fault
// handlers, the C library hooks) and the sections of the linker script (hal/cortex_m/ld/cortex-m-sections.ld) are
// shared too; a board library adds its peripherals, its MEMORY map, machine_name() and expected_cpu_part()
// (docs/porting.md).
#pragma once

#include <cstddef>
#include <cstdint>

#include "lashid/hal/isr_byte_queue.hpp"
#include "lashid/hal/status.hpp"

namespace lashid::hal::cortex_m {

// ---- The core and the board ------------------------------------------------------------------------------------

/// The machine the image was linked for ("mps2-an386", "netduinoplus2", ...; defined by the board library), and the
/// core the compiler targeted.
const char* machine_name();
const char* core_name();
/// Names the QEMU machine in the image for the host tools: in a board's source, LASHID_CORTEX_M_MACHINE_TAG("name")
/// puts "name" (NUL-terminated) in the section `.lashid.machine`, which is not loaded (no flash, no RAM; kept by the
/// linker as a non-allocated orphan, like .comment). `lashid hil` reads it and refuses to boot the image on another
/// machine, where it would only fault or hang until the time limit. An image without it is run as it is.
#define LASHID_CORTEX_M_MACHINE_TAG(name) \
  __asm__(".pushsection .lashid.machine,\"\",%progbits\n\t.asciz \"" name "\"\n\t.popsection")
/// Names, the same way (section `.lashid.plant`, not loaded), where the image's plant is: "port" (played by `lashid
/// hil` over a plant-port UART) or "own" (the board's own actuator and sensor: `lashid hil --physical-plant`). `lashid
/// hil` refuses a run whose mode does not match, which would otherwise wait on a UART until its time limit.
#define LASHID_CORTEX_M_PLANT_TAG(kind) \
  __asm__(".pushsection .lashid.plant,\"\",%progbits\n\t.asciz \"" kind "\"\n\t.popsection")
/// CPUID.PartNo expected on the machine the image was linked for (0xC23 Cortex-M3, 0xC24 M4, 0xC27 M7; defined by the
/// board library) and the one the CPU reports: they differ when an image runs on the wrong -machine.
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

// ---- The link UART's receive interrupt ----------------------------------------------------------------------------

/// The link UART's receive interrupt: external interrupt LASHID_LINK_RX_IRQ (a compile definition the board library
/// sets PUBLIC on lashid_hal_cortex_m, and checks against its own constant) runs LinkRx_IRQHandler, which the board
/// defines: it moves every received byte into link_rx_queue() and counts the bytes its UART lost (overrun, framing,
/// noise). The sequencer reads the link once per sample; a UART without a FIFO holds one byte, and at 115200 baud 11
/// arrive per millisecond, so without the interrupt a command sent during a run would overrun it on a chip (QEMU
/// holds bytes back instead, which hid it).
///
/// 256 bytes: 22 ms of input at 115200 baud, where the sequencer polls the link every sample (about 12 bytes
/// arrive between two polls at 1 kHz), and more than one maximal frame (kMaxFrame), the longest a command can be.
using LinkRxQueue = IsrByteQueue<256>;
LinkRxQueue& link_rx_queue();
/// Enables external interrupt `irq` in the NVIC (ISER; priority left at its reset value, the highest).
void enable_irq(std::uint32_t irq);
/// Disables external interrupt `irq` in the NVIC (ICER).
void disable_irq(std::uint32_t irq);
/// Sets external interrupt `irq` pending (ISPR): its handler runs once it is enabled and the priority allows.
void pend_irq(std::uint32_t irq);
/// Clears external interrupt `irq`'s pending state (ICPR).
void clear_pending_irq(std::uint32_t irq);

/// Sleeps (WFI) until the next interrupt unless `ready()` holds. Interrupts are masked from the check to WFI, so an
/// interrupt that comes in between is not slept through: a pending interrupt ends WFI even when masked, and its
/// handler runs at once after. Wake sources: every enabled interrupt, SysTick's zero events among them (a board that
/// sleeps starts SysTick with RELOAD + 1 = its sample period, so no sleep outlasts one period). Call with interrupts
/// enabled. In QEMU a sleeping core frees the host's CPU (a polling one keeps a host core busy and slows the
/// emulated UARTs that the host feeds).
template <class Ready>
void sleep_until_interrupt_unless(Ready ready) {
  __asm__ volatile("cpsid i" ::: "memory");
  if (!ready()) __asm__ volatile("dsb\n\twfi" ::: "memory");
  __asm__ volatile("cpsie i\n\tisb" ::: "memory");
}
/// The platforms' link_read: the queued bytes in order (kOk), kLinkError once where bytes were lost between two of
/// them, else kWouldBlock.
Status read_link_rx(std::uint8_t& byte);

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

// ---- SysTick ----------------------------------------------------------------------------------------------------------

class SysTickClock {
 public:
  static constexpr std::uint32_t kMaxReload = 0x00FF'FFFF;  ///< the counter is 24 bits wide

  /// Starts SysTick on the processor clock with RELOAD = `reload` (period reload + 1 cycles) and its wrap interrupt,
  /// and restarts cycles() from 0. Interrupts must not stay masked for longer than one period (2^24 cycles = 671 ms
  /// at 25 MHz, 100 ms at 168 MHz), or wraps are lost.
  static void start(std::uint32_t reload = kMaxReload);
  static void stop();
  /// CPU clock cycles since start(), modulo 2^32 (differences are valid across one wrap: 171.8 s at 25 MHz, 25.6 s at
  /// 168 MHz).
  /// Monotonic also when called with interrupts masked (a pending wrap is accounted for).
  static std::uint32_t cycles();
  /// SysTick wraps counted so far (the interrupt count, for tests).
  static std::uint32_t wraps();
  /// Cycles until the next zero event (SysTick's current value: it counts down to 0).
  static std::uint32_t cycles_to_zero_event();
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

}  // namespace lashid::hal::cortex_m
