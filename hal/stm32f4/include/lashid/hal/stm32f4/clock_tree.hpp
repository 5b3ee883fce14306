// The STM32F405's clock tree at start-up: from the 16 MHz HSI it runs on after reset to SYSCLK = 168 MHz from the
// main PLL on the HSE crystal, with the flash wait states, the voltage scale and the bus prescalers that speed
// needs. Written from RM0090 (rev 19) for the STM32F405/407: 7.2 (clocks), 7.3.1-7.3.3 (RCC_CR, RCC_PLLCFGR,
// RCC_CFGR), 3.5.1 and Table 10 (flash wait states at 2.7-3.6 V), 3.9.1 (FLASH_ACR), 5.4.1 (PWR_CR.VOS).
//
//   ClockPlan          the PLL's M, N, P, Q and the prescalers, with every limit of the manual checked (valid())
//   plan_for_hse(hz)   the plan for 168 MHz from a crystal of `hz` (VCO input 2 MHz where it divides, as RM0090
//                      recommends against jitter, else 1 MHz; VCO 336 MHz; USB 48 MHz)
//   ClockSettings      the register values a plan gives (ClockPlan::settings(), constexpr)
//   start_clock_tree   the sequence, on any RegisterBus: bounded waits, a ClockStart status, never a hang
//
// On QEMU's netduinoplus2 the RCC is an unimplemented-device stub (writes ignored, reads 0) and SYSCLK is fixed at
// 168 MHz: RCC_CR reading 0, which the chip cannot do (it runs on the HSI, so HSIRDY is set), is taken for that
// stub, and nothing is written. Freestanding, no heap: the image calls it first thing in main.
#pragma once

#include <cstdint>

#include "lashid/hal/stm32f4/register_bus.hpp"

namespace lashid::hal::stm32f4 {

namespace clock_registers {
// RCC (RM0090 2.3: 0x40023800), FLASH interface (0x40023C00), PWR (0x40007000)
inline constexpr std::uintptr_t kRccCr = 0x4002'3800;
inline constexpr std::uintptr_t kRccPllcfgr = 0x4002'3804;
inline constexpr std::uintptr_t kRccCfgr = 0x4002'3808;
inline constexpr std::uintptr_t kRccApb1enr = 0x4002'3840;
inline constexpr std::uintptr_t kFlashAcr = 0x4002'3C00;
inline constexpr std::uintptr_t kPwrCr = 0x4000'7000;
// RCC_CR (7.3.1)
inline constexpr std::uint32_t kCrHsiOn = 1U << 0;
inline constexpr std::uint32_t kCrHsiRdy = 1U << 1;
inline constexpr std::uint32_t kCrHseOn = 1U << 16;
inline constexpr std::uint32_t kCrHseRdy = 1U << 17;
inline constexpr std::uint32_t kCrHseByp = 1U << 18;
inline constexpr std::uint32_t kCrPllOn = 1U << 24;
inline constexpr std::uint32_t kCrPllRdy = 1U << 25;
inline constexpr std::uint32_t kCrPllI2sOn = 1U << 26;
inline constexpr std::uint32_t kCrPllI2sRdy = 1U << 27;
// RCC_PLLCFGR (7.3.2): PLLM [5:0], PLLN [14:6], PLLP [17:16] (P = 2, 4, 6, 8 as 0..3), PLLSRC [22] (1 = HSE),
// PLLQ [27:24]. The other bits (15, 21:18, 23, 31:28) are reserved and must keep their reset value (reset value
// 0x24003010: bit 29 is set). PLLM and PLLSRC may be written only while the PLL and the PLLI2S are both off.
inline constexpr std::uint32_t kPllcfgrReserved = 0xF0BC'8000U;
inline constexpr std::uint32_t kPllcfgrSrcHse = 1U << 22;
// RCC_CFGR (7.3.3): SW [1:0] and SWS [3:2] (0 HSI, 1 HSE, 2 PLL), HPRE [7:4], PPRE1 [12:10], PPRE2 [15:13]
inline constexpr std::uint32_t kCfgrSwMask = 0x3U;
inline constexpr std::uint32_t kCfgrSwsMask = 0x3U << 2;
inline constexpr std::uint32_t kCfgrPrescalerMask = (0xFU << 4) | (0x7U << 10) | (0x7U << 13);
inline constexpr std::uint32_t kSwHsi = 0U;
inline constexpr std::uint32_t kSwPll = 2U;
// RCC_APB1ENR (7.3.13): PWREN
inline constexpr std::uint32_t kApb1enrPwrEn = 1U << 28;
// FLASH_ACR (3.9.1): LATENCY [2:0], PRFTEN [8], ICEN [9], DCEN [10]
inline constexpr std::uint32_t kAcrLatencyMask = 0x7U;
inline constexpr std::uint32_t kAcrPrefetchAndCaches = (1U << 8) | (1U << 9) | (1U << 10);
// PWR_CR (5.4.1, STM32F405/407): VOS [14], 1 = scale 1, needed above 144 MHz
inline constexpr std::uint32_t kPwrCrVos = 1U << 14;
}  // namespace clock_registers

/// The register values of a ClockPlan, as start_clock_tree writes them (ClockPlan::settings()).
struct ClockSettings {
  bool valid = false;  ///< ClockPlan::valid(): start_clock_tree writes nothing otherwise
  bool hse_bypass = false;
  std::uint32_t pllcfgr_fields = 0;   ///< RCC_PLLCFGR without its reserved bits
  std::uint32_t cfgr_prescalers = 0;  ///< RCC_CFGR's HPRE, PPRE1, PPRE2
  std::uint32_t flash_wait_states = 0;
  std::uint32_t ready_poll_limit = 0;
};

/// How SYSCLK is made from the HSE: SYSCLK = HSE / M * N / P, USB clock = HSE / M * N / Q, HCLK = SYSCLK / AHB,
/// PCLK1 = HCLK / APB1, PCLK2 = HCLK / APB2.
struct ClockPlan {
  std::uint32_t hse_hz = 0;
  bool hse_bypass = false;  ///< an external clock on OSC_IN instead of a crystal (RCC_CR.HSEBYP)
  std::uint32_t pll_m = 0, pll_n = 0, pll_p = 2, pll_q = 0;
  std::uint32_t ahb_divider = 1, apb1_divider = 4, apb2_divider = 2;
  /// Reads of a ready flag before its wait gives up. The slowest is the crystal's start-up (typically 2 ms, RM0090
  /// 7.2.1); a poll takes a few cycles of the 16 MHz HSI, so 500,000 polls wait a few hundred ms.
  std::uint32_t ready_poll_limit = 500'000;

  constexpr std::uint32_t vco_input_hz() const { return pll_m == 0 ? 0 : hse_hz / pll_m; }
  constexpr std::uint64_t vco_output_hz() const { return std::uint64_t{vco_input_hz()} * pll_n; }
  constexpr std::uint32_t sysclk_hz() const { return pll_p == 0 ? 0 : static_cast<std::uint32_t>(vco_output_hz() / pll_p); }
  constexpr std::uint32_t usb_hz() const { return pll_q == 0 ? 0 : static_cast<std::uint32_t>(vco_output_hz() / pll_q); }
  constexpr std::uint32_t hclk_hz() const { return sysclk_hz() / ahb_divider; }
  constexpr std::uint32_t pclk1_hz() const { return hclk_hz() / apb1_divider; }
  constexpr std::uint32_t pclk2_hz() const { return hclk_hz() / apb2_divider; }
  /// Table 10 (2.7-3.6 V): one wait state per started 30 MHz of HCLK beyond the first.
  constexpr std::uint32_t flash_wait_states() const { return hclk_hz() == 0 ? 0 : (hclk_hz() - 1U) / 30'000'000U; }

  /// Every rule of RM0090 the plan must keep: HSE 4-26 MHz (1-50 MHz bypassed), M 2..63 with a VCO input of 1-2 MHz
  /// and no remainder, N 50..432 with a VCO output of 100-432 MHz, P in {2, 4, 6, 8}, Q 2..15, SYSCLK <= 168 MHz,
  /// PCLK1 <= 42 MHz, PCLK2 <= 84 MHz, dividers the prescalers have, and at most 7 wait states.
  constexpr bool valid() const {
    const bool hse = hse_bypass ? hse_hz >= 1'000'000 && hse_hz <= 50'000'000
                                : hse_hz >= 4'000'000 && hse_hz <= 26'000'000;
    const bool m = pll_m >= 2 && pll_m <= 63 && hse_hz % pll_m == 0 && vco_input_hz() >= 1'000'000 &&
                   vco_input_hz() <= 2'000'000;
    const bool n = pll_n >= 50 && pll_n <= 432 && vco_output_hz() >= 100'000'000 && vco_output_hz() <= 432'000'000;
    const bool p = pll_p == 2 || pll_p == 4 || pll_p == 6 || pll_p == 8;
    const bool q = pll_q >= 2 && pll_q <= 15;
    const auto power_of_two = [](std::uint32_t d, std::uint32_t max) {
      return d >= 1 && d <= max && (d & (d - 1U)) == 0 && d != 32;  // AHB: 1..512 without 32; APB: 1..16
    };
    const bool dividers = power_of_two(ahb_divider, 512) && power_of_two(apb1_divider, 16) &&
                          power_of_two(apb2_divider, 16);
    return hse && m && n && p && q && dividers && sysclk_hz() <= 168'000'000 && pclk1_hz() <= 42'000'000 &&
           pclk2_hz() <= 84'000'000 && flash_wait_states() <= 7 && ready_poll_limit > 0;
  }

  /// What the start-up sequence writes, all of it computed here (at compile time for a constexpr plan).
  constexpr ClockSettings settings() const;

  /// RCC_PLLCFGR's fields (the reserved bits are the register's own).
  constexpr std::uint32_t pllcfgr_fields() const {
    return pll_m | (pll_n << 6) | ((pll_p / 2U - 1U) << 16) | clock_registers::kPllcfgrSrcHse | (pll_q << 24);
  }
  /// RCC_CFGR's HPRE, PPRE1 and PPRE2 fields for the dividers.
  constexpr std::uint32_t cfgr_prescalers() const {
    const auto log2 = [](std::uint32_t d) {
      std::uint32_t k = 0;
      while ((1U << k) < d) ++k;
      return k;
    };
    // HPRE: 0xxx = /1, 1000 = /2 ... 1111 = /512 (no /32); PPREx: 0xx = /1, 100 = /2 ... 111 = /16.
    const std::uint32_t hpre = ahb_divider == 1 ? 0U : 0x8U | (log2(ahb_divider) - (ahb_divider > 32 ? 2U : 1U));
    const std::uint32_t ppre1 = apb1_divider == 1 ? 0U : 0x4U | (log2(apb1_divider) - 1U);
    const std::uint32_t ppre2 = apb2_divider == 1 ? 0U : 0x4U | (log2(apb2_divider) - 1U);
    return (hpre << 4) | (ppre1 << 10) | (ppre2 << 13);
  }
};

constexpr ClockSettings ClockPlan::settings() const {
  return {valid(), hse_bypass, pllcfgr_fields(), cfgr_prescalers(), flash_wait_states(), ready_poll_limit};
}

/// 168 MHz (the STM32F405's maximum) from a crystal of `hse_hz`: VCO input 2 MHz if it divides the crystal, else
/// 1 MHz; VCO output 336 MHz, P = 2, Q = 7 (48 MHz for USB); AHB /1, APB1 /4 (42 MHz), APB2 /2 (84 MHz). A crystal
/// that is not a whole number of MHz gives an invalid plan (valid() is false): choose M and N by hand then.
constexpr ClockPlan plan_for_hse(std::uint32_t hse_hz, bool bypass = false) {
  ClockPlan plan;
  plan.hse_hz = hse_hz;
  plan.hse_bypass = bypass;
  const std::uint32_t input_hz = hse_hz % 2'000'000 == 0 ? 2'000'000U : 1'000'000U;
  if (hse_hz % input_hz != 0) return plan;  // pll_m = 0: invalid
  plan.pll_m = hse_hz / input_hz;
  plan.pll_n = 336'000'000U / input_hz;
  plan.pll_p = 2;
  plan.pll_q = 7;
  return plan;
}

/// What start_clock_tree did. Only kOnPll and kFixedByEmulator leave the plan's clocks running.
enum class [[nodiscard]] ClockStart : std::uint8_t {
  kOnPll = 0,            ///< SYSCLK is the PLL on the HSE, at the plan's frequencies
  kFixedByEmulator,      ///< RCC_CR read 0: no RCC (QEMU's stub); the emulator's fixed clock is taken, nothing written
  kInvalidPlan,          ///< the plan breaks a rule of RM0090 (ClockPlan::valid()); nothing written
  kHsiNotReady,          ///< leaving a running PLL: the HSI did not come up
  kSwitchNotDone,        ///< RCC_CFGR.SWS did not follow SW (to the HSI, or to the PLL)
  kPllDidNotStop,        ///< the PLL or the PLLI2S, already on, did not stop (RCC_PLLCFGR cannot change while they run)
  kPllConfigRefused,     ///< RCC_PLLCFGR did not read back as written: SYSCLK stays on the HSI
  kHseDidNotStop,        ///< the HSE, on with the other bypass setting, did not stop (HSEBYP needs it off)
  kHseNotReady,          ///< the crystal did not start: HSE is switched off again, SYSCLK stays on the HSI
  kFlashLatencyRefused,  ///< FLASH_ACR did not take the wait states: SYSCLK stays on the HSI
  kPllNotReady,          ///< the PLL did not lock: SYSCLK stays on the HSI
};

constexpr const char* to_string(ClockStart s) {
  switch (s) {
    case ClockStart::kOnPll: return "on the PLL";
    case ClockStart::kFixedByEmulator: return "no RCC (an emulator's fixed clock)";
    case ClockStart::kInvalidPlan: return "the clock plan breaks a rule of RM0090";
    case ClockStart::kHsiNotReady: return "the HSI did not become ready";
    case ClockStart::kSwitchNotDone: return "SYSCLK did not switch (RCC_CFGR.SWS)";
    case ClockStart::kPllDidNotStop: return "the running PLL or PLLI2S did not stop";
    case ClockStart::kPllConfigRefused: return "RCC_PLLCFGR did not take the PLL's configuration";
    case ClockStart::kHseDidNotStop: return "the HSE did not stop (to change HSEBYP)";
    case ClockStart::kHseNotReady: return "the HSE crystal did not start";
    case ClockStart::kFlashLatencyRefused: return "FLASH_ACR did not take the wait states";
    case ClockStart::kPllNotReady: return "the PLL did not lock";
  }
  return "unknown";
}

/// Whether the clocks the plan computes are the ones running (the PLL, or the emulator's fixed clock).
constexpr bool runs_as_planned(ClockStart s) { return s == ClockStart::kOnPll || s == ClockStart::kFixedByEmulator; }

/// The start-up sequence (RM0090 7.2 and 3.5.1): leave a PLL already running (a boot loader's) for the HSI; stop the
/// PLL and the PLLI2S; start the HSE; voltage scale 1; flash wait states, prefetch and caches, checked by reading
/// back, before the clock rises; bus prescalers; configure the PLL (read back) and start it; switch SYSCLK to it.
/// Every wait is bounded by plan.ready_poll_limit. A failure after SYSCLK is on the HSI leaves it there; the two that
/// can come before (kHsiNotReady, and kSwitchNotDone on the way to the HSI) leave the clock the image was started
/// with (a boot loader's).
template <RegisterBus Bus>
ClockStart start_clock_tree(Bus& bus, const ClockSettings& plan) {
  using namespace clock_registers;
  if (bus.read(kRccCr) == 0U) return ClockStart::kFixedByEmulator;
  if (!plan.valid) return ClockStart::kInvalidPlan;
  const std::uint32_t limit = plan.ready_poll_limit;
  // PLLCFGR can be written only while the PLL is off, and the PLL cannot stop while it is SYSCLK: go to the HSI.
  if ((bus.read(kRccCfgr) & kCfgrSwsMask) != (kSwHsi << 2)) {
    bus.write(kRccCr, bus.read(kRccCr) | kCrHsiOn);
    if (!wait_for_bits(bus, kRccCr, kCrHsiRdy, kCrHsiRdy, limit)) return ClockStart::kHsiNotReady;
    bus.write(kRccCfgr, (bus.read(kRccCfgr) & ~kCfgrSwMask) | kSwHsi);
    if (!wait_for_bits(bus, kRccCfgr, kCfgrSwsMask, kSwHsi << 2, limit)) return ClockStart::kSwitchNotDone;
  }
  if ((bus.read(kRccCr) & (kCrPllOn | kCrPllI2sOn)) != 0U) {
    bus.write(kRccCr, bus.read(kRccCr) & ~(kCrPllOn | kCrPllI2sOn));
    if (!wait_for_bits(bus, kRccCr, kCrPllRdy | kCrPllI2sRdy, 0U, limit)) return ClockStart::kPllDidNotStop;
  }
  // HSEBYP may be written only while the HSE is off (7.3.1): stop it first if it runs the other way.
  if (((bus.read(kRccCr) & kCrHseByp) != 0U) != plan.hse_bypass) {
    bus.write(kRccCr, bus.read(kRccCr) & ~kCrHseOn);
    if (!wait_for_bits(bus, kRccCr, kCrHseRdy, 0U, limit)) return ClockStart::kHseDidNotStop;
    bus.write(kRccCr, bus.read(kRccCr) ^ kCrHseByp);
  }
  bus.write(kRccCr, bus.read(kRccCr) | kCrHseOn);
  if (!wait_for_bits(bus, kRccCr, kCrHseRdy, kCrHseRdy, limit)) {
    bus.write(kRccCr, bus.read(kRccCr) & ~kCrHseOn);
    return ClockStart::kHseNotReady;
  }
  // Scale 1 (the reset value on the F405/407; written in case a boot loader lowered it). The PWR clock first.
  bus.write(kRccApb1enr, bus.read(kRccApb1enr) | kApb1enrPwrEn);
  (void)bus.read(kRccApb1enr);  // the enable takes effect before PWR is accessed (ES0182 2.1.13)
  bus.write(kPwrCr, bus.read(kPwrCr) | kPwrCrVos);
  // Wait states before the clock rises, and read back (3.5.1: "check that the new number of wait states is taken
  // into account by reading the FLASH_ACR register").
  const std::uint32_t latency = plan.flash_wait_states;
  bus.write(kFlashAcr, (bus.read(kFlashAcr) & ~kAcrLatencyMask) | latency | kAcrPrefetchAndCaches);
  if ((bus.read(kFlashAcr) & kAcrLatencyMask) != latency) return ClockStart::kFlashLatencyRefused;
  bus.write(kRccCfgr, (bus.read(kRccCfgr) & ~kCfgrPrescalerMask) | plan.cfgr_prescalers);
  bus.write(kRccPllcfgr, (bus.read(kRccPllcfgr) & kPllcfgrReserved) | plan.pllcfgr_fields);
  if ((bus.read(kRccPllcfgr) & ~kPllcfgrReserved) != plan.pllcfgr_fields) return ClockStart::kPllConfigRefused;
  bus.write(kRccCr, bus.read(kRccCr) | kCrPllOn);
  if (!wait_for_bits(bus, kRccCr, kCrPllRdy, kCrPllRdy, limit)) return ClockStart::kPllNotReady;
  bus.write(kRccCfgr, (bus.read(kRccCfgr) & ~kCfgrSwMask) | kSwPll);
  if (!wait_for_bits(bus, kRccCfgr, kCfgrSwsMask, kSwPll << 2, limit)) {
    bus.write(kRccCfgr, (bus.read(kRccCfgr) & ~kCfgrSwMask) | kSwHsi);  // ask for the HSI again
    return ClockStart::kSwitchNotDone;
  }
  return ClockStart::kOnPll;
}

}  // namespace lashid::hal::stm32f4
