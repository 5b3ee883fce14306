// Minimal ARM semihosting (v2.0): console output and exit. No newlib rdimon: that library brings file I/O and
// malloc. Operation numbers and the AArch32 calling convention (operation in r0, argument in r1, result in r0,
// trap `bkpt 0xAB` on M-profile) are from Arm's "Semihosting for AArch32 and AArch64" specification.
//
// LASHID_SEMIHOSTING=0 (CMake option LASHID_SEMIHOSTING OFF) is for a board without a debugger: there the first
// `bkpt` would fault (and the fault handler's own `bkpt` lock the core up). The console is then silent and exit()
// parks the core, its code in lashid_exit_code for a debugger attached later.
#include "lashid/hal/cortex_m.hpp"

#ifndef LASHID_SEMIHOSTING
#error "LASHID_SEMIHOSTING must be 0 or 1 (hal/cortex_m/CMakeLists.txt)"
#endif

#if !LASHID_SEMIHOSTING

extern "C" {
// The last exit code, for a debugger (no host to receive it).
volatile int lashid_exit_code = -1;
}

namespace lashid::hal::cortex_m::semihosting {

void write(const char*) {}

void write_char(char) {}

void exit(int code) {
  lashid_exit_code = code;
  __asm__ volatile("cpsid i" ::: "memory");
  for (;;) {
    __asm__ volatile("wfi" ::: "memory");
  }
}

}  // namespace lashid::hal::cortex_m::semihosting

#else

namespace lashid::hal::cortex_m::semihosting {

namespace {
constexpr std::uint32_t kSysWritec = 0x03;
constexpr std::uint32_t kSysWrite0 = 0x04;
constexpr std::uint32_t kSysExit = 0x18;
constexpr std::uint32_t kSysExitExtended = 0x20;
constexpr std::uint32_t kAdpStoppedApplicationExit = 0x20026;
constexpr std::uint32_t kAdpStoppedRunTimeErrorUnknown = 0x20023;

std::uint32_t call(std::uint32_t operation, const void* argument) {
  std::uint32_t result = 0;
  __asm__ volatile(
      "mov r0, %[op]\n\t"
      "mov r1, %[arg]\n\t"
      "bkpt 0xAB\n\t"
      "mov %[result], r0"
      : [result] "=r"(result)
      : [op] "r"(operation), [arg] "r"(argument)
      : "r0", "r1", "memory");
  return result;
}
}  // namespace

void write(const char* text) { (void)call(kSysWrite0, text); }

void write_char(char c) { (void)call(kSysWritec, &c); }

void exit(int code) {
  if (code == 0) {
    // AArch32 SYS_EXIT: r1 holds the reason itself (not a pointer); ApplicationExit means status 0.
    (void)call(kSysExit, reinterpret_cast<const void*>(kAdpStoppedApplicationExit));
  } else {
    // SYS_EXIT_EXTENDED: r1 points at {reason, subcode}; the subcode is the exit status.
    const std::uint32_t block[2] = {kAdpStoppedApplicationExit, static_cast<std::uint32_t>(code)};
    (void)call(kSysExitExtended, block);
    // A host without SYS_EXIT_EXTENDED: at least exit non-zero.
    (void)call(kSysExit, reinterpret_cast<const void*>(kAdpStoppedRunTimeErrorUnknown));
  }
  for (;;) {
    __asm__ volatile("" ::: "memory");  // not under a semihosting host: stop here
  }
}

}  // namespace lashid::hal::cortex_m::semihosting

#endif  // LASHID_SEMIHOSTING
