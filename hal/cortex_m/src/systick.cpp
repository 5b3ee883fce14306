// SysTick as a 32-bit monotonic cycle counter, and the sample timer on top of it.
//
// The 24-bit counter counts down from RELOAD to 0 on the processor clock (CLKSOURCE = 1: 25 MHz on mps2, 168 MHz on
// QEMU's netduinoplus2; the external reference clock is board-specific, HCLK/8 on the STM32F4 and 1 MHz on mps2, so
// the processor clock is the one source every board has); reaching 0
// pends the SysTick exception and the next cycle reloads. The handler counts these "zero events" in g_wraps, so
// cycles = wraps * (RELOAD + 1) + (cycles since the last zero event), where a counter value c means
// (c == 0 ? 0 : RELOAD + 1 - c) cycles since that event. Arithmetic is modulo 2^32, so differences of cycles() are
// valid across the 32-bit wrap whatever RELOAD is.
#include "lashid/hal/cortex_m.hpp"
#include "registers.hpp"

namespace {
volatile std::uint32_t g_wraps = 0;
std::uint32_t g_period = lashid::hal::cortex_m::SysTickClock::kMaxReload + 1U;
}  // namespace

extern "C" void SysTick_Handler() { g_wraps = g_wraps + 1U; }

namespace lashid::hal::cortex_m {

void SysTickClock::start(std::uint32_t reload) {
  using namespace detail;
  if (reload == 0U || reload > kMaxReload) reload = kMaxReload;
  reg(kSystCsr) = 0;
  g_period = reload + 1U;
  g_wraps = 0;
  reg(kSystRvr) = reload;
  reg(kSystCvr) = 0;  // any write clears the counter (and COUNTFLAG); it loads RELOAD on the next cycle
  reg(kIcsr) = 1U << 25;  // PENDSTCLR: no stale SysTick exception
  reg(kSystCsr) = kSystEnable | kSystTickInt | kSystClkSourceCpu;
}

void SysTickClock::stop() {
  using namespace detail;
  reg(kSystCsr) = 0;
}

std::uint32_t SysTickClock::wraps() { return g_wraps; }

std::uint32_t SysTickClock::cycles_to_zero_event() { return detail::reg(detail::kSystCvr); }

std::uint32_t SysTickClock::cycles() {
  using namespace detail;
  std::uint32_t wraps = 0;
  std::uint32_t current = 0;
  bool pending = false;
  do {  // retry when the handler ran in between: wraps and current must belong together
    wraps = g_wraps;
    current = reg(kSystCvr);
    pending = (reg(kIcsr) & kIcsrPendStSet) != 0U;
  } while (wraps != g_wraps);
  if (pending) {
    // A zero event the handler has not counted yet (interrupts masked, or we run at higher priority). `current` may
    // be from before or after it: read again, certainly after it.
    current = reg(kSystCvr);
    ++wraps;
  }
  const std::uint32_t since = current == 0U ? 0U : g_period - current;
  return wraps * g_period + since;
}

void SampleTimer::start(std::uint32_t period_cycles) {
  period_ = period_cycles;
  next_ = SysTickClock::cycles();
  overruns_ = 0;
}

Status SampleTimer::wait() {
  next_ += period_;
  std::uint32_t now = SysTickClock::cycles();
  if (static_cast<std::int32_t>(now - next_) > 0) {
    ++overruns_;
    next_ = now;
    return Status::kTimeout;
  }
  while (static_cast<std::int32_t>(now - next_) < 0) {
    // Asleep until the next zero event where that comes no later than the tick (SysTick's interrupt wakes the
    // core); the last cycles before the tick polled.
    const std::uint32_t left = next_ - now;
    sleep_until_interrupt_unless([left] { return SysTickClock::cycles_to_zero_event() > left; });
    now = SysTickClock::cycles();
  }
  return Status::kOk;
}

}  // namespace lashid::hal::cortex_m
