// Startup and C/C++ runtime policy for every Cortex-M image of the project (boards mps2 and stm32f4): vector table,
// reset, fault handlers, stack measurement, and the few newlib/libstdc++ hooks a bare-metal image needs.
//
// This object is forced into every image by the linker script (EXTERN(lashid_cortex_m_vectors)), so every definition
// below wins over the C library's before the library is searched: abort(), __assert_func(), atexit(), _exit() and
// __cxa_pure_virtual() end the run through semihosting with a message. There is deliberately NO _sbrk (and the
// linker script defines no `end` symbol and asserts that no _sbrk got linked): anything that needs the heap
// (malloc, operator new, stdio buffers) fails to link instead of silently getting one.
//
// Reset order: [asm] FPU access (CPACR CP10/CP11, DSB, ISB) -> SP -> paint the stack; [C++] copy .data, zero .bss,
// VTOR, the stack guard (MPU), preinit/init arrays (static constructors), main(), finish(main's result).
#include <cstddef>
#include <cstdint>

#include "lashid/hal/cortex_m.hpp"
#include "registers.hpp"

// Linker script symbols (hal/cortex_m/ld/cortex-m-sections.ld).
extern "C" {
extern std::uint32_t __stack_guard[];
extern std::uint32_t __stack_limit[];
extern std::uint32_t __stack_top[];
extern std::uint32_t __data_start[];
extern std::uint32_t __data_end[];
extern const std::uint32_t __data_load[];
extern std::uint32_t __bss_start[];
extern std::uint32_t __bss_end[];
using InitFunction = void (*)();
extern const InitFunction __preinit_array_start[];
extern const InitFunction __preinit_array_end[];
extern const InitFunction __init_array_start[];
extern const InitFunction __init_array_end[];

[[noreturn]] void Reset_Handler();
void NMI_Handler();
void HardFault_Handler();
void Default_Handler();
void SysTick_Handler();  // systick.cpp
void LinkRx_IRQHandler();  // the board's: its link UART's receive interrupt (lashid/hal/cortex_m.hpp)
// The plant port's receive interrupt: defined by an image that sleeps while it waits for the plant's answer
// (firmware/targets/remote_identification_board.hpp); in any other image its line is never enabled.
[[gnu::weak, gnu::alias("Default_Handler")]] void PlantRx_IRQHandler();
}

// The application's main(), called through its assembler name: C++ forbids a program to call ::main directly.
extern "C" int lashid_cortex_m_application_main() __asm__("main");

#define LASHID_STR2(x) #x
#define LASHID_STR(x) LASHID_STR2(x)
// The stack paint as an assembler literal; must equal lashid::hal::cortex_m::kStackPaint.
#define LASHID_CORTEX_M_STACK_PAINT 0x5AC55AC5
static_assert(LASHID_CORTEX_M_STACK_PAINT == lashid::hal::cortex_m::kStackPaint);

// ---- Vector table ------------------------------------------------------------------------------------------------------

namespace {

using Handler = void (*)();
constexpr std::size_t kSystemExceptions = 16;
// The board library sets the number of its external interrupt lines (mps2: 32, STM32F405: 82, RM0090 Table 61), so
// that an unexpected interrupt of any line ends in Default_Handler with its number instead of a jump through garbage.
#if !defined(LASHID_EXTERNAL_IRQS)
#error "LASHID_EXTERNAL_IRQS: the board library must define its number of external interrupt lines"
#endif
constexpr std::size_t kExternalInterrupts = LASHID_EXTERNAL_IRQS;
#if !defined(LASHID_LINK_RX_IRQ)
#error "LASHID_LINK_RX_IRQ: the board library must name its link UART's receive interrupt line"
#endif
constexpr std::size_t kLinkRxIrq = LASHID_LINK_RX_IRQ;
static_assert(kLinkRxIrq < kExternalInterrupts, "LASHID_LINK_RX_IRQ: not one of the board's interrupt lines");
#if !defined(LASHID_PLANT_RX_IRQ)
#error "LASHID_PLANT_RX_IRQ: the board library must name its plant port UART's receive interrupt line"
#endif
constexpr std::size_t kPlantRxIrq = LASHID_PLANT_RX_IRQ;
static_assert(kPlantRxIrq < kExternalInterrupts && kPlantRxIrq != kLinkRxIrq,
              "LASHID_PLANT_RX_IRQ: not one of the board's interrupt lines, or the link's");

struct VectorTable {
  void* initial_sp;
  Handler handlers[kSystemExceptions - 1 + kExternalInterrupts];
};

constexpr VectorTable make_vectors() {
  VectorTable t{__stack_top, {}};
  for (Handler& h : t.handlers) h = Default_Handler;
  t.handlers[0] = Reset_Handler;       // 1
  t.handlers[1] = NMI_Handler;         // 2
  t.handlers[2] = HardFault_Handler;   // 3: MemManage/BusFault/UsageFault (4..6) are not enabled and escalate here
  t.handlers[6] = t.handlers[7] = t.handlers[8] = t.handlers[9] = nullptr;  // 7..10: reserved
  t.handlers[12] = nullptr;                                                  // 13: reserved
  t.handlers[14] = SysTick_Handler;    // 15
  t.handlers[kSystemExceptions - 1 + kLinkRxIrq] = LinkRx_IRQHandler;  // 16 + LASHID_LINK_RX_IRQ
  t.handlers[kSystemExceptions - 1 + kPlantRxIrq] = PlantRx_IRQHandler;  // 16 + LASHID_PLANT_RX_IRQ
  return t;
}

}  // namespace

// extern: a namespace-scope const has internal linkage, even in extern "C", and the linker script's
// EXTERN(lashid_cortex_m_vectors) would find nothing by that name (the table came in only with Reset_Handler).
extern "C" {
[[gnu::used, gnu::section(".isr_vector")]] extern constinit const VectorTable lashid_cortex_m_vectors = make_vectors();
}

// ---- Reset -------------------------------------------------------------------------------------------------------------

extern "C" [[noreturn]] void lashid_cortex_m_start();

// Naked: runs before anything may use the stack or an FP register, so no compiler-generated code at all.
extern "C" [[gnu::naked, noreturn]] void Reset_Handler() {
  __asm__ volatile(
      // Interrupts masked until our vector table is installed (lashid_cortex_m_start): a boot loader that jumps here
      // may leave a peripheral interrupting, whose handler (its own) would run over the RAM being initialised.
      "cpsid i\n\t"
#if defined(__ARM_FP)
      // CPACR |= CP10, CP11 full access; DSB + ISB so that the next instruction already sees the FPU enabled
      // (ARMv7-M ARM, B3.2.20). Any FP instruction before this point would raise a NOCP UsageFault.
      "ldr r0, =0xE000ED88\n\t"
      "ldr r1, [r0]\n\t"
      "orr r1, r1, #0x00F00000\n\t"
      "str r1, [r0]\n\t"
      "dsb\n\t"
      "isb\n\t"
#endif
      // The vector table already set SP; set it again for a debugger or boot loader that jumps here.
      "ldr r0, =__stack_top\n\t"
      "mov sp, r0\n\t"
      // Paint [__stack_limit, __stack_top) with the pattern, one word at a time (nothing is on the stack yet).
      "ldr r0, =__stack_limit\n\t"
      "ldr r1, =__stack_top\n\t"
      "ldr r2, =" LASHID_STR(LASHID_CORTEX_M_STACK_PAINT) "\n\t"
      "1:\n\t"
      "cmp r0, r1\n\t"
      "bhs 2f\n\t"
      "str r2, [r0], #4\n\t"
      "b 1b\n\t"
      "2:\n\t"
      "b lashid_cortex_m_start\n\t"
      ".ltorg\n\t");
}

namespace {

// The MPU's region 0 over [__stack_guard, __stack_limit): no access, not executable; the default memory map
// everywhere else (PRIVDEFENA: everything here runs privileged). A push into the guard is a MemManage fault, taken
// as HardFault (MemManage is not enabled), whose handler sees the stack pointer below __stack_limit and reports the
// overflow. HardFault runs with the MPU off (HFNMIENA = 0), so the handler itself is not stopped by the guard: it
// runs its report in the guard, its own stack (HardFault_Handler).
// Without an MPU (MPU_TYPE.DREGION = 0) or with a guard the MPU cannot describe, nothing is set.
void enable_stack_guard() {
  using namespace lashid::hal::cortex_m::detail;
  const auto base = reinterpret_cast<std::uintptr_t>(__stack_guard);
  const std::uintptr_t size = reinterpret_cast<std::uintptr_t>(__stack_limit) - base;
  if (((reg(kMpuType) >> 8) & 0xFFU) == 0U || size < 32U || (size & (size - 1U)) != 0U || (base & (size - 1U)) != 0U) {
    return;
  }
  std::uint32_t size_field = 0;  // SIZE: the region is 2^(SIZE + 1) bytes
  while ((std::uintptr_t{2} << size_field) < size) ++size_field;
  reg(kMpuRnr) = 0U;
  reg(kMpuRbar) = static_cast<std::uint32_t>(base);
  reg(kMpuRasr) = kMpuRasrXn | (size_field << 1) | kMpuRasrEnable;  // AP = 000: no access, privileged or not
  reg(kMpuCtrl) = kMpuCtrlPrivDefEna | kMpuCtrlEnable;
  __asm__ volatile("dsb\n\tisb" ::: "memory");
}

}  // namespace

extern "C" [[noreturn]] void lashid_cortex_m_start() {
  using namespace lashid::hal::cortex_m::detail;
  // .data from its load address in flash, .bss to zero. Word loops over linker-provided bounds.
  const std::uint32_t* src = __data_load;
  for (std::uint32_t* dst = __data_start; dst < __data_end;) *dst++ = *src++;
  for (std::uint32_t* dst = __bss_start; dst < __bss_end;) *dst++ = 0U;
  reg(kVtor) = static_cast<std::uint32_t>(reinterpret_cast<std::uintptr_t>(&lashid_cortex_m_vectors));
  __asm__ volatile("dsb\n\tisb" ::: "memory");
  __asm__ volatile("cpsie i" ::: "memory");  // masked since Reset_Handler; the handlers are ours from here on
  enable_stack_guard();
  for (const InitFunction* f = __preinit_array_start; f < __preinit_array_end; ++f) (*f)();
  for (const InitFunction* f = __init_array_start; f < __init_array_end; ++f) (*f)();
  lashid::hal::cortex_m::finish(lashid_cortex_m_application_main());
}

// ---- Faults and unexpected exceptions ----------------------------------------------------------------------------------

namespace {

void say(const char* text) { lashid::hal::cortex_m::semihosting::write(text); }

// The fault handlers' report is written in pieces, each number through a 12-byte buffer (no 240-byte message): they
// run on the fault stack, the 128 bytes of the guard (below), and the build's stack check (cmake/StackDepth.cmake,
// test <image>_stack_fits) fails if their deepest path does not fit it. No floating point here either: a lazily
// preserved FP context would be saved into the faulting frame, which may be beyond the stack.
void say_hex(std::uint32_t value) {
  lashid::hal::cortex_m::Text<12> t;
  t.hex(value);
  say(t.c_str());
}

}  // namespace

// Called by HardFault_Handler on the fault stack with the exception frame (r0-r3, r12, lr, pc, xPSR) of the faulting
// context, or with nullptr when the stack had overflowed (the frame could not be stacked there). An overflow may also
// leave a frame: a push that reaches into the guard from a few bytes above it faults with the stack pointer still
// above (the push is abandoned), and the 8-word frame fits there. The MPU then names the address, in the guard.
extern "C" [[noreturn, gnu::used]] void lashid_cortex_m_hard_fault(const std::uint32_t* frame) {
  using namespace lashid::hal::cortex_m;
  using namespace lashid::hal::cortex_m::detail;
  const std::uint32_t cfsr = reg(kCfsr);
  const std::uintptr_t mmfar = reg(kMmfar);
  const bool into_guard = (cfsr & kCfsrMmarValid) != 0U && mmfar >= reinterpret_cast<std::uintptr_t>(__stack_guard) &&
                          mmfar < reinterpret_cast<std::uintptr_t>(__stack_limit);
  // 1: the stack pointer was above the stack (HardFault_Handler), so there is no frame to read.
  const bool corrupted = reinterpret_cast<std::uintptr_t>(frame) == 1U;
  if (corrupted) {
    say("\nlashid: HardFault: the stack pointer was above the stack (corrupted): no frame read; cfsr=");
  } else if (frame == nullptr || into_guard) {
    say(frame == nullptr ? "\nlashid: HardFault: stack overflow (the stack pointer went below __stack_limit, "
                         : "\nlashid: HardFault: stack overflow (an access to the guard under the stack, ");
    Text<12> size;
    size << static_cast<std::uint32_t>(stack_size_bytes());
    say(size.c_str());
    say(" bytes reserved) cfsr=");
  } else {
    say("\nlashid: HardFault pc=");
    say_hex(frame[6]);
    say(" lr=");
    say_hex(frame[5]);
    say(" cfsr=");
  }
  say_hex(cfsr);
  say(" hfsr=");
  say_hex(reg(kHfsr));
  // The fault address registers only where CFSR says they hold one.
  if ((cfsr & kCfsrMmarValid) != 0U) {
    say(" mmfar=");
    say_hex(reg(kMmfar));
  }
  if ((cfsr & kCfsrBfarValid) != 0U) {
    say(" bfar=");
    say_hex(reg(kBfar));
  }
  say("\n");
  if ((cfsr & kCfsrNoCp) != 0U) say("lashid: UsageFault NOCP: coprocessor (FPU) access while disabled\n");
  semihosting::exit(!corrupted && (frame == nullptr || into_guard) ? kExitStackOverflow : kExitHardFault);
}

// The fault stack: HardFault and NMI never run their report on the stack they interrupted, which may be within a few
// bytes of its end (a fault there would run the report below RAM: a bus fault inside HardFault, a lockup). Before
// anything is pushed, MSP moves to __stack_limit, the top of the 128-byte guard under the stack, and the report runs
// in the guard: no one else can have written it (the MPU denies every access there, but to HardFault and NMI, which
// run with the MPU off: HFNMIENA = 0), and these handlers never return, so nothing of it has to survive. Without an
// MPU the guard is plain RAM, which an overflow may have written: the report does not read it. The faulting stack is
// only read, for the frame, and only when its stack pointer is within the stack ([__stack_limit, __stack_top - 32]):
// below it the frame was not stacked (the overflow), and the report says "stack overflow"; above it the stack pointer
// was corrupted (reading there could fault again, a lockup), and the report says so. Only MSP is used by this
// platform (no thread stack); a frame on PSP is read the same way.
extern "C" [[gnu::naked]] void HardFault_Handler() {
  __asm__ volatile(
      "tst lr, #4\n\t"  // EXC_RETURN bit 2: which stack holds the frame
      "ite eq\n\t"
      "mrseq r0, msp\n\t"
      "mrsne r0, psp\n\t"
      "ldr r1, =__stack_limit\n\t"
      "msr msp, r1\n\t"  // the fault stack, from here on
      "cmp r0, r1\n\t"
      "it lo\n\t"
      "movlo r0, #0\n\t"  // below the stack: no frame
      "ldr r1, =__stack_top - 32\n\t"
      "cmp r0, r1\n\t"
      "it hi\n\t"
      "movhi r0, #1\n\t"  // no whole frame below the top (a corrupted stack pointer): not read either
      "b lashid_cortex_m_hard_fault\n\t"
      ".ltorg\n\t");
}

extern "C" [[noreturn, gnu::used]] void lashid_cortex_m_nmi() {
  say("\nlashid: unexpected NMI\n");
  lashid::hal::cortex_m::semihosting::exit(lashid::hal::cortex_m::kExitUnexpectedIrq);
}

// NMI runs with the MPU off too, and may come at any depth: on the fault stack as well (see HardFault_Handler).
extern "C" [[gnu::naked]] void NMI_Handler() {
  __asm__ volatile(
      "ldr r0, =__stack_limit\n\t"
      "msr msp, r0\n\t"
      "b lashid_cortex_m_nmi\n\t"
      ".ltorg\n\t");
}

extern "C" void Default_Handler() {
  using namespace lashid::hal::cortex_m;
  Text<64> t;
  t << "\nlashid: unexpected exception " << (detail::reg(detail::kIcsr) & 0x1FFU) << "\n";
  say(t.c_str());
  semihosting::exit(kExitUnexpectedIrq);
}

// ---- Runtime policy (newlib / libstdc++ hooks) -------------------------------------------------------------------------

extern "C" {

[[noreturn]] void abort() {
  say("\nlashid: abort()\n");
  lashid::hal::cortex_m::semihosting::exit(lashid::hal::cortex_m::kExitAbort);
}

// newlib's assert() target (used when NDEBUG is not defined, e.g. eigen_assert in a Debug build).
[[noreturn]] void __assert_func(const char* file, int line, const char* function, const char* expression) {
  using namespace lashid::hal::cortex_m;
  Text<256> t;
  t << "\nlashid: assertion failed: " << (expression != nullptr ? expression : "?") << " in "
    << (function != nullptr ? function : "?") << " at " << (file != nullptr ? file : "?") << ':'
    << static_cast<std::int32_t>(line) << "\n";
  say(t.c_str());
  semihosting::exit(kExitAbort);
}

// Static destructors never run on this target (main's return ends the run through semihosting), so they are not
// registered: no atexit table, no allocation for one.
int atexit(void (*)()) { return 0; }

// std::exit() / exit() end here after newlib's exit processing.
[[noreturn]] void _exit(int code) { lashid::hal::cortex_m::semihosting::exit(code); }

[[noreturn]] void __cxa_pure_virtual() {
  say("\nlashid: pure virtual call\n");
  lashid::hal::cortex_m::semihosting::exit(lashid::hal::cortex_m::kExitAbort);
}

}  // extern "C"

// ---- Platform queries, stack, finish -----------------------------------------------------------------------------------

namespace lashid::hal::cortex_m {

const char* core_name() {
#if defined(__ARM_ARCH_7EM__) && defined(__ARM_FP) && (__ARM_FP & 8)
  return "Cortex-M7 (ARMv7E-M, FPv5 double precision, hard float)";
#elif defined(__ARM_ARCH_7EM__) && defined(__ARM_FP)
  return "Cortex-M4F (ARMv7E-M, FPv4 single precision, hard float)";
#elif defined(__ARM_ARCH_7EM__)
  return "ARMv7E-M (soft float)";
#elif defined(__ARM_ARCH_7M__)
  return "Cortex-M3 (ARMv7-M, soft float)";
#else
  return "unknown core";
#endif
}

std::uint32_t cpu_part() { return (detail::reg(detail::kCpuid) >> 4) & 0xFFFU; }

bool fpu_enabled() {
  return (detail::reg(detail::kCpacr) & detail::kCpacrCp10Cp11Full) == detail::kCpacrCp10Cp11Full;
}

std::uint32_t fp_features() {
  // MVFR0 exists only with an FPU; on a Cortex-M3 the address is reserved (QEMU reads 0 there; avoid it anyway).
  return cpu_part() == 0xC23U ? 0U : detail::reg(detail::kMvfr0);
}

std::size_t stack_size_bytes() {
  // uintptr_t and size_t are both `unsigned int` on the Cortex-M ABI (a cast is a -Wuseless-cast error there).
  return reinterpret_cast<std::uintptr_t>(__stack_top) - reinterpret_cast<std::uintptr_t>(__stack_limit);
}

std::size_t stack_high_water_bytes() {
  const volatile std::uint32_t* p = __stack_limit;
  const volatile std::uint32_t* const top = __stack_top;
  while (p < top && *p == kStackPaint) ++p;
  return reinterpret_cast<std::uintptr_t>(__stack_top) - reinterpret_cast<std::uintptr_t>(p);
}

void finish(int code) {
  const std::size_t used = stack_high_water_bytes();
  const std::size_t size = stack_size_bytes();
  // The whole paint gone (or all but the last word): the stack may have overflowed below __stack_limit.
  const bool overflow = used + sizeof(std::uint32_t) >= size;
  Text<160> t;
  t << "lashid: exit " << static_cast<std::int32_t>(code) << ", stack high-water "
    << static_cast<std::uint32_t>(used) << " of " << static_cast<std::uint32_t>(size) << " bytes\n";
  say(t.c_str());
  if (overflow) {
    say("lashid: STACK OVERFLOW (the stack paint is used up)\n");
    if (code == 0) code = kExitStackOverflow;
  }
  semihosting::exit(code);
}

}  // namespace lashid::hal::cortex_m
