// Platform smoke test of the Cortex-M boards (QEMU mps2-an385/an386/an500, and netduinoplus2 for the STM32F405), run
// by the test smoke_runs_in_qemu:
//   - the console: a banner over the link UART (UART0 / USART1: stdout of QEMU) and semihosting (stderr)
//   - startup: .data copied, .bss zeroed, static constructors run
//   - the core: CPUID matches the machine the image was linked for
//   - the FPU: enabled by the reset handler before any float code; FP math in hardware (would fault otherwise)
//   - Eigen, fixed size, no exceptions, no heap (EIGEN_NO_MALLOC): a 4x4 LDLT solve; the estimator's headers
//   - SysTick: cycles() against a loop of known instruction count under -icount shift=0 (1 ns per instruction: 40
//     instructions per 25 MHz cycle on mps2, 125/21 per 168 MHz cycle on the STM32F405), monotonic across wraps,
//     also with interrupts masked
//   - the sample tick and the byte link of a hal::Board built on the board's platform half
//   - the stack high-water mark
// Exit code 0 when every check passes, 1 otherwise (and the platform's own codes for faults).
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <cmath>
#include <cstdint>

#include "lashid/estimator/design.hpp"
#include "lashid/hal/board.hpp"

// The board of the build (LASHID_BOARD, a compile definition from firmware/smoke/CMakeLists.txt): its namespace, link
// UART, platform half, and the instructions per SysTick cycle under -icount shift=0 as a fraction.
#if defined(LASHID_BOARD_STM32F4)
#include "lashid/hal/stm32f4.hpp"
namespace board = lashid::hal::stm32f4;
using Platform = board::Stm32f4Platform;
constexpr board::Usart kUart{board::kUsart1};
constexpr std::uint32_t kPerCycleNum = board::kIcount0InstructionsPerCycleNum;
constexpr std::uint32_t kPerCycleDen = board::kIcount0InstructionsPerCycleDen;
#else
#include "lashid/hal/mps2.hpp"
namespace board = lashid::hal::mps2;
using Platform = board::Mps2Platform;
constexpr board::Mps2Uart kUart{board::kUart0Base};
constexpr std::uint32_t kPerCycleNum = board::kInstructionsPerCycleIcount0;
constexpr std::uint32_t kPerCycleDen = 1;
#endif

using lashid::hal::Status;

namespace {

int g_failures = 0;

void out(const char* text) { (void)kUart.write(text); }

void both(const char* text) {
  out(text);
  board::semihosting::write(text);
}

void check(bool ok, const char* what) {
  if (ok) return;
  ++g_failures;
  board::Text<160> t;
  t << "FAIL: " << what << "\n";
  both(t.c_str());
}

// Exactly 2 * n instructions (n >= 1): subs + bne per iteration, in assembly so the compiler cannot change it.
void known_loop(std::uint32_t n) {
  __asm__ volatile(
      "1:\n\t"
      "subs %0, %0, #1\n\t"
      "bne 1b"
      : "+r"(n)
      :
      : "cc");
}

// ---- startup: .data, .bss, static constructors ------------------------------------------------------------------------

volatile std::uint32_t g_seed = 7;  // .data
std::uint32_t g_zero;               // .bss
// Dynamically initialised (its constructor reads a volatile, so it cannot be constant-initialised): the reset handler
// must have run the init array. Its destructor is registered through atexit(), which the platform makes a no-op.
struct StaticInitProbe {
  StaticInitProbe() : value(g_seed * 6U) {}
  ~StaticInitProbe() { value = 0; }
  StaticInitProbe(const StaticInitProbe&) = delete;
  StaticInitProbe& operator=(const StaticInitProbe&) = delete;
  std::uint32_t value;
};
StaticInitProbe g_probe;

void check_startup() {
  board::Text<120> t;
  t << "startup: .data " << static_cast<std::uint32_t>(g_seed) << ", .bss " << g_zero << ", static constructor "
    << g_probe.value << "\n";
  out(t.c_str());
  check(g_seed == 7U && g_zero == 0U, ".data/.bss initialisation");
  check(g_probe.value == 42U, "static constructor did not run");
}

// ---- core and FPU ---------------------------------------------------------------------------------------------------

void check_core() {
  board::Text<160> t;
  t << "cpu: CPUID.PartNo ";
  t.hex(board::cpu_part(), 3) << ", expected for " << board::machine_name() << ' ';
  t.hex(board::expected_cpu_part(), 3) << "\n";
  out(t.c_str());
  check(board::cpu_part() == board::expected_cpu_part(), "CPUID does not match the machine the image was linked for");
}

void check_fpu() {
  board::Text<200> t;
  if constexpr (board::kBuiltWithFpu) {
    const std::uint32_t mvfr0 = board::fp_features();
    t << "fpu: built for hard float; CPACR CP10/CP11 " << (board::fpu_enabled() ? "full access" : "NOT enabled")
      << ", MVFR0 ";
    t.hex(mvfr0) << " (single precision " << ((mvfr0 >> 4) & 0xFU) << ", double precision " << ((mvfr0 >> 8) & 0xFU)
                 << ")\n";
    out(t.c_str());
    check(board::fpu_enabled(), "FPU not enabled by the reset handler");
    check(((mvfr0 >> 4) & 0xFU) == 2U, "no single-precision FPU");
#if defined(__ARM_FP) && (__ARM_FP & 8)
    check(((mvfr0 >> 8) & 0xFU) == 2U, "built for a double-precision FPU, the CPU has none");
#endif
  } else {
    t << "fpu: none used (soft float)\n";
    out(t.c_str());
  }
  // Float math from volatile inputs, so it runs here, in FP instructions on FPU builds (vmul, vdiv, vsqrt): without
  // the CPACR enable each would raise a NOCP UsageFault -> HardFault -> exit 135.
  volatile float a = 2.0f;
  volatile float b = 3.0f;
  const float r = std::sqrt(a) * b + a / b;  // 3 sqrt(2) + 2/3
  const float expected = 4.9093073f;
  t.clear();
  t << "float: sqrt(2) * 3 + 2 / 3 = ";
  t.fixed(r, 7) << "\n";
  out(t.c_str());
  check(std::fabs(r - expected) < 1e-6f, "float arithmetic");
  volatile double c = 2.0;
  const double d = std::sqrt(c) * 3.0;  // FPv5-D16: hardware double; elsewhere libgcc
  check(std::fabs(d - 4.242640687119285) < 1e-12, "double arithmetic");
}

// ---- Eigen and the estimator's headers ---------------------------------------------------------------------------------

void check_eigen() {
  using Matrix4 = Eigen::Matrix<float, 4, 4>;
  using Vector4 = Eigen::Matrix<float, 4, 1>;
  volatile float scale = 1.0f;  // keeps the solve at run time
  Matrix4 a;
  a << 4.0f, 1.0f, 0.0f, 0.5f,  //
      1.0f, 3.0f, 1.0f, 0.0f,   //
      0.0f, 1.0f, 2.0f, 0.5f,   //
      0.5f, 0.0f, 0.5f, 1.5f;
  a *= static_cast<float>(scale);
  const Vector4 x_true(1.0f, -2.0f, 0.5f, 3.0f);
  const Vector4 b = a * x_true;
  const Eigen::LDLT<Matrix4> ldlt(a);
  const Vector4 x = ldlt.solve(b);
  const float error = (x - x_true).cwiseAbs().maxCoeff();
  board::Text<200> t;
  t << "eigen: 4x4 LDLT solve, x = [";
  for (int i = 0; i < 4; ++i) t.fixed(x(i), 5) << (i < 3 ? ", " : "]");
  t << ", max error ";
  t.fixed(error, 7) << "\n";
  out(t.c_str());
  check(ldlt.info() == Eigen::Success && ldlt.isPositive(), "LDLT of an SPD matrix");
  check(error < 1e-5f, "LDLT solution");

  // The paper's DIS design (Section 3.5) validated by the estimator, as the firmware will.
  lashid::est::ExperimentDesign<float, 6> design;
  design.v_min = -3.0f;
  design.v_max = 4.0f;
  design.V << -3.0f, -2.0f, -1.0f, 1.0f, 2.0f, 3.0f;
  check(design.validate() == lashid::est::Status::kOk, "estimator: the paper's DIS design validates");
}

// ---- SysTick -----------------------------------------------------------------------------------------------------------

void check_cycles() {
  using board::SysTickClock;
  // Cycles to instructions (rounded), and one cycle's worth of instructions rounded up: the resolution.
  const auto to_instructions = [](std::uint32_t c) {
    return static_cast<std::uint32_t>((std::uint64_t{c} * kPerCycleNum + kPerCycleDen / 2U) / kPerCycleDen);
  };
  constexpr std::uint32_t kPerCycle = (kPerCycleNum + kPerCycleDen - 1U) / kPerCycleDen;  // 40 (mps2), 6 (stm32f4)
  SysTickClock::start();

  // Back-to-back reads: the cost of one cycles() call, below one cycle's resolution.
  const std::uint32_t e0 = SysTickClock::cycles();
  const std::uint32_t e1 = SysTickClock::cycles();

  constexpr std::uint32_t kIterations = 1'000'000;
  constexpr std::uint32_t kExpected = 2 * kIterations;
  const std::uint32_t t0 = SysTickClock::cycles();
  known_loop(kIterations);
  const std::uint32_t t1 = SysTickClock::cycles();
  const std::uint32_t cycles = t1 - t0;
  const std::uint32_t instructions = to_instructions(cycles);
  const auto deviation = static_cast<std::int32_t>(instructions - kExpected);
  // Less the cost of the cycles() call between the two counter reads (0 cycles at -O2, 2 at -O0).
  const auto corrected = static_cast<std::int32_t>(to_instructions(cycles - (e1 - e0)) - kExpected);

  board::Text<300> t;
  t << "systick: back-to-back cycles() " << (e1 - e0) << " cycles; known loop " << kIterations
    << " x 2 instructions = " << kExpected << " instructions expected; measured " << cycles << " cycles x "
    << kPerCycleNum << " / " << kPerCycleDen << " = " << instructions << " instructions (" << deviation << ", resolution " << kPerCycle << ")\n";
  both(t.c_str());
  // Within the quantisation: one cycle (40 or 6 instructions) either way for each of the two reads.
  check(corrected >= -2 * static_cast<std::int32_t>(kPerCycle) && corrected <= 2 * static_cast<std::int32_t>(kPerCycle),
        "known loop: cycles x instructions per cycle != instructions (is QEMU running with -icount shift=0?)");

  // Monotonic across wraps: a short period (1024 cycles) wraps every 40960 (mps2) or 6095 (stm32f4) instructions.
  SysTickClock::start(1023);
  std::uint32_t previous = SysTickClock::cycles();
  bool monotonic = true;
  const std::uint32_t w0 = SysTickClock::wraps();
  const std::uint32_t s0 = previous;
  for (int i = 0; i < 20'000; ++i) {
    const std::uint32_t now = SysTickClock::cycles();
    monotonic = monotonic && static_cast<std::int32_t>(now - previous) >= 0;
    previous = now;
  }
  // With interrupts masked: wraps stay pending, cycles() must account for them (each spin below 1 period).
  for (int round = 0; round < 8; ++round) {
    __asm__ volatile("cpsid i" ::: "memory");
    const std::uint32_t start = SysTickClock::cycles();
    std::uint32_t prev = start;
    while (prev - start < 900U) {
      const std::uint32_t now = SysTickClock::cycles();
      monotonic = monotonic && static_cast<std::int32_t>(now - prev) >= 0;
      prev = now;
    }
    __asm__ volatile("cpsie i" ::: "memory");
    const std::uint32_t after = SysTickClock::cycles();
    monotonic = monotonic && static_cast<std::int32_t>(after - prev) >= 0;
    previous = after;
  }
  const std::uint32_t wraps = SysTickClock::wraps() - w0;
  // The same known loop with a wrap (and its handler) every 1024 cycles.
  const std::uint32_t u0 = SysTickClock::cycles();
  known_loop(kIterations);
  const std::uint32_t u1 = SysTickClock::cycles();
  t.clear();
  t << "systick: 1024-cycle period: " << wraps << " wraps in " << (previous - s0) << " cycles, monotonic "
    << (monotonic ? "yes" : "NO") << "; known loop " << (u1 - u0) << " cycles (" << cycles << " without wraps)\n";
  out(t.c_str());
  check(monotonic, "cycles() went backwards");
  check(wraps > 10U, "SysTick wraps not counted");
  // Each wrap costs the handler's few instructions: within 1% of the wrap-free count.
  check((u1 - u0) >= cycles - 1U && (u1 - u0) <= cycles + cycles / 100U, "cycles() across wraps");
  SysTickClock::start();
}

// ---- A hal::Board on the platform --------------------------------------------------------------------------------------

// The platform half (link, clock, sample tick) plus a trivial in-image "actuator": y = 0.5 v.
class SmokeBoard {
 public:
  explicit SmokeBoard(std::uint32_t period) { platform_.init(period); }
  Status actuate(float v) {
    if (!(v >= -10.0f && v <= 10.0f)) return Status::kOutOfRange;
    v_ = v;
    return Status::kOk;
  }
  Status measure(float& y) {
    y = 0.5f * v_;
    return Status::kOk;
  }
  Status wait_for_sample_tick() { return platform_.wait_for_sample_tick(); }
  Status link_write(const std::uint8_t* data, std::size_t size) { return platform_.link_write(data, size); }
  Status link_read(std::uint8_t& byte) { return platform_.link_read(byte); }
  std::uint32_t cycles() const { return platform_.cycles(); }

 private:
  Platform platform_;
  float v_ = 0.0f;
};
static_assert(lashid::hal::Board<SmokeBoard>);

void check_board() {
  constexpr std::uint32_t kPeriod = board::kSystemClockHz / 10'000;  // 100 us: 2,500 cycles at 25 MHz
  constexpr int kSamples = 20;
  SmokeBoard board(kPeriod);
  const std::uint32_t start = board.cycles();
  int late = 0;
  float sum = 0.0f;
  for (int k = 0; k < kSamples; ++k) {
    if (board.wait_for_sample_tick() != Status::kOk) ++late;
    float y = 0.0f;
    check(board.actuate(static_cast<float>(k) * 0.25f) == Status::kOk, "actuate");
    check(board.measure(y) == Status::kOk, "measure");
    sum += y;
  }
  const std::uint32_t elapsed = board.cycles() - start;
  check(board.actuate(11.0f) == Status::kOutOfRange, "actuate out of range");
  // Overrun one period on purpose: the next tick is late, reported, not skipped.
  known_loop(kPeriod * kPerCycleNum / kPerCycleDen);  // 2 periods of instructions
  const Status overrun = board.wait_for_sample_tick();
  std::uint8_t byte = 0;
  const Status read = board.link_read(byte);
  const char message[] = "link: bytes over the link UART\n";
  const Status write = board.link_write(reinterpret_cast<const std::uint8_t*>(message), sizeof message - 1);

  board::Text<240> t;
  t << "board: " << static_cast<std::uint32_t>(kSamples) << " sample ticks of " << kPeriod << " cycles in " << elapsed
    << " cycles, " << static_cast<std::uint32_t>(late) << " late; overrun -> " << lashid::hal::to_string(overrun)
    << "; link_read -> " << lashid::hal::to_string(read) << "; sum y = ";
  t.fixed(sum, 2) << "\n";
  out(t.c_str());
  check(late == 0, "sample ticks late");
  check(elapsed >= kSamples * kPeriod && elapsed < (kSamples + 1) * kPeriod, "sample period");
  check(overrun == Status::kTimeout, "an overrun sample tick reports kTimeout");
  check(read == Status::kOk || read == Status::kWouldBlock, "link_read");
  check(write == Status::kOk, "link_write");
  check(std::fabs(sum - 23.75f) < 1e-4f, "board samples");
}

}  // namespace

int main() {
#if defined(LASHID_BOARD_STM32F4)
  // The board's clocks first, as its identification image starts them (on QEMU, whose RCC reads 0, the emulator's
  // fixed 168 MHz is kept and nothing is written).
  const board::ClockStart clock = board::start_clock_tree();
#endif
  kUart.init();
  {
    board::Text<160> t;
    t << "lashid smoke " << board::core_name() << " on " << board::machine_name() << "\n";
    both(t.c_str());
  }
#if defined(LASHID_BOARD_STM32F4)
  both("clocks: ");
  both(board::to_string(clock));
  both("\n");
  check(board::runs_as_planned(clock), "clock tree");
#endif
  check_startup();
  check_core();
  check_fpu();
  check_eigen();
  check_cycles();
  check_board();
  {
    board::Text<160> t;
    t << "stack: high-water " << static_cast<std::uint32_t>(board::stack_high_water_bytes()) << " of "
      << static_cast<std::uint32_t>(board::stack_size_bytes()) << " bytes\n";
    out(t.c_str());
    t.clear();
    t << "lashid smoke: " << (g_failures == 0 ? "all checks passed" : "FAILED") << "\n";
    both(t.c_str());
  }
  return g_failures == 0 ? 0 : 1;
}
