// A stack overflow that lands with little stack left (hal/cortex_m/src/startup.cpp, HardFault_Handler): the stack
// pointer is 40 bytes above __stack_limit and a 56-byte push reaches 16 bytes into the guard. The push is abandoned
// with the stack pointer unchanged, so the exception frame (8 words) is stacked above the limit: a valid frame, with
// 8 bytes of stack left under it. The fault report must not run there (it would run through the guard and below RAM:
// a bus fault inside HardFault, a lockup on the STM32F405), and the fault is an overflow: "stack overflow", exit
// kExitStackOverflow (137). CTest stack_overflow_near_the_limit_is_reported_as_such (firmware/smoke/CMakeLists.txt).
//
// The stack pointer is set by hand, so that the case is exact on every core: a recursion would land anywhere.
int main() {
  __asm__ volatile(
      "ldr r0, =__stack_limit\n\t"
      "adds r0, #40\n\t"
      "mov sp, r0\n\t"
      "push {r0-r12, lr}\n\t"  // 14 words: from __stack_limit - 16 up; faults at once on the guard
      "1: b 1b\n\t"            // no guard (no MPU): nothing faulted; the test fails by its time limit
      ".ltorg\n\t" ::: "r0", "memory");
  return 0;
}
