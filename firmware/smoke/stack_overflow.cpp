// The fault path of a stack overflow (hal/cortex_m/src/startup.cpp, HardFault_Handler): a recursion that never ends
// runs the stack below __stack_limit. The image must end with "stack overflow" and kExitStackOverflow (137), not
// lock up in its own fault handler (QEMU: "Lockup: can't escalate", SIGABRT). CTest
// stack_overflow_is_reported_as_such (firmware/smoke/CMakeLists.txt).
#include <cstdint>

namespace {

// Each call keeps a frame of 64 words alive across the next call (the sum uses it after the call returns), so the
// compiler can neither inline the recursion away nor turn it into a loop.
std::uint32_t deeper(std::uint32_t depth) {
  volatile std::uint32_t frame[64];
  for (std::uint32_t i = 0; i < 64; ++i) frame[i] = depth + i;
  std::uint32_t sum = deeper(depth + 1);
  for (std::uint32_t i = 0; i < 64; ++i) sum += frame[i];
  return sum;
}

}  // namespace

int main() { return static_cast<int>(deeper(0) & 0x7FU); }
