// The STM32F405 image's start-up sequences (hal/stm32f4/include/lashid/hal/stm32f4/), run on the PC against a model
// of the registers they touch. QEMU cannot check them: its netduinoplus2 has no RCC, flash interface or GPIO model.
// Expected register values are derived by hand from RM0090 (rev 19) field layouts and reset values, each written out
// beside its derivation; the model enforces the manual's ordering rules and records any breach.
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "lashid/hal/stm32f4/clock_tree.hpp"
#include "lashid/hal/stm32f4/usart_pins.hpp"

namespace {

using namespace lashid::hal::stm32f4;
namespace cr = clock_registers;

constexpr std::uintptr_t kGpioA = pin_registers::kGpioA;
constexpr std::uintptr_t kRccAhb1enr = pin_registers::kRccAhb1enr;

// RCC, FLASH, PWR and GPIOA as the chip has them, with the ready flags following their enables after a few reads of
// RCC_CR, SWS following SW when the source is ready, and FLASH_ACR taking (or, as a fault, refusing) the latency.
class ChipModel {
 public:
  bool crystal_starts = true, crystal_stops = true, pll_locks = true, flash_takes_latency = true, no_rcc = false;
  bool pllcfgr_writable = true;
  int ready_after_reads = 3;
  std::uint32_t reads = 0;
  std::vector<std::pair<std::uintptr_t, std::uint32_t>> writes;
  std::vector<const char*> breaches;  // rules of RM0090 the sequence broke
  std::map<std::uintptr_t, std::uint32_t> reg{
      {cr::kRccCr, 0x0000'7883U},        // HSION, HSIRDY, HSITRIM = 16, a factory HSICAL (7.3.1: 0x0000 XX83)
      {cr::kRccPllcfgr, 0x2400'3010U},   // 7.3.2
      {cr::kRccCfgr, 0x0000'0000U},      // 7.3.3
      {cr::kRccApb1enr, 0x0000'0000U},   // 7.3.13
      {kRccAhb1enr, 0x0010'0000U},       // 7.3.10: CCMDATARAMEN
      {cr::kFlashAcr, 0x0000'0000U},     // 3.9.1
      {cr::kPwrCr, 0x0000'4000U},        // 5.4.1: VOS = 1 on the F405/407
      {kGpioA + pin_registers::kModer, 0xA800'0000U},    // 8.4.1, port A (the debug pins)
      {kGpioA + pin_registers::kOtyper, 0x0000'0000U},
      {kGpioA + pin_registers::kOspeedr, 0x0C00'0000U},  // 8.4.3, port A
      {kGpioA + pin_registers::kPupdr, 0x6400'0000U},    // 8.4.4, port A
      {kGpioA + pin_registers::kAfrl, 0x0000'0000U},
      {kGpioA + pin_registers::kAfrh, 0x0000'0000U},
  };

  std::uint32_t read(std::uintptr_t address) {
    ++reads;
    if (no_rcc && address >= cr::kRccCr && address < cr::kRccCr + 0x400) return 0;
    if ((address == cr::kRccCr || address == cr::kRccCfgr) && pending_ > 0 && --pending_ == 0) settle();
    return reg.at(address);
  }

  void write(std::uintptr_t address, std::uint32_t value) {
    writes.emplace_back(address, value);
    std::uint32_t& r = reg.at(address);
    if (address == cr::kRccCr) {
      const std::uint32_t ready = cr::kCrHsiRdy | cr::kCrHseRdy | cr::kCrPllRdy | cr::kCrPllI2sRdy;
      if (((r ^ value) & cr::kCrHseByp) != 0 && (r & cr::kCrHseOn) != 0) breaches.push_back("HSEBYP changed with HSE on");
      r = (r & ready) | (value & ~ready);  // the ready flags are read-only
      // 7.3.1: PLLON and HSEON cannot be reset while the PLL (on the HSE) is SYSCLK.
      if (sysclk_source() == cr::kSwPll) r |= cr::kCrPllOn | cr::kCrHseOn;
      if ((r & cr::kCrPllOn) == 0) r &= ~cr::kCrPllRdy;
      if ((r & cr::kCrPllI2sOn) == 0) r &= ~cr::kCrPllI2sRdy;
      if ((r & cr::kCrHseOn) == 0 && crystal_stops) r &= ~cr::kCrHseRdy;
      pending_ = ready_after_reads;
    } else if (address == cr::kRccPllcfgr) {
      // 7.3.2: PLLM and PLLSRC only with the PLL and the PLLI2S off (the chip then keeps the old values).
      const std::uint32_t running = cr::kCrPllOn | cr::kCrPllRdy | cr::kCrPllI2sOn | cr::kCrPllI2sRdy;
      if ((reg.at(cr::kRccCr) & running) != 0) {
        breaches.push_back("PLLCFGR written with the PLL or the PLLI2S on");
      } else if (pllcfgr_writable) {
        r = value;
      }
    } else if (address == cr::kRccCfgr) {
      const std::uint32_t sw = value & cr::kCfgrSwMask;
      if (sw == cr::kSwPll && (reg.at(cr::kFlashAcr) & cr::kAcrLatencyMask) < 5) {
        breaches.push_back("SYSCLK switched to 168 MHz with fewer than 5 wait states");
      }
      if (sw == cr::kSwPll && (value & cr::kCfgrPrescalerMask) != ((0x5U << 10) | (0x4U << 13))) {
        breaches.push_back("SYSCLK switched to 168 MHz before the APB prescalers");
      }
      r = (r & cr::kCfgrSwsMask) | (value & ~cr::kCfgrSwsMask);  // SWS is read-only
      pending_ = ready_after_reads;
    } else if (address == cr::kFlashAcr) {
      r = flash_takes_latency ? value : (value & ~cr::kAcrLatencyMask) | (r & cr::kAcrLatencyMask);
    } else if (address == cr::kPwrCr && (reg.at(cr::kRccApb1enr) & cr::kApb1enrPwrEn) == 0) {
      breaches.push_back("PWR_CR written with the PWR clock off");
    } else {
      r = value;
    }
  }

  std::uint32_t sysclk_source() const { return (reg.at(cr::kRccCfgr) & cr::kCfgrSwsMask) >> 2; }

 private:
  void settle() {
    std::uint32_t& c = reg.at(cr::kRccCr);
    if ((c & cr::kCrHsiOn) != 0) c |= cr::kCrHsiRdy;
    if ((c & cr::kCrHseOn) != 0 && crystal_starts) c |= cr::kCrHseRdy;
    if ((c & cr::kCrPllOn) != 0 && pll_locks && (c & cr::kCrHseRdy) != 0) c |= cr::kCrPllRdy;
    if ((c & cr::kCrPllI2sOn) != 0) c |= cr::kCrPllI2sRdy;
    std::uint32_t& cfgr = reg.at(cr::kRccCfgr);
    const std::uint32_t sw = cfgr & cr::kCfgrSwMask;
    const bool ready = sw == cr::kSwHsi ? (c & cr::kCrHsiRdy) != 0 : (c & cr::kCrPllRdy) != 0;
    if (ready) cfgr = (cfgr & ~cr::kCfgrSwsMask) | (sw << 2);
  }
  int pending_ = 0;
};
static_assert(RegisterBus<ChipModel>);

ClockSettings test_plan() {
  ClockPlan plan = plan_for_hse(8'000'000);
  plan.ready_poll_limit = 1000;
  return plan.settings();
}

// 8 MHz crystal: M = 4 (2 MHz into the VCO), N = 168 (336 MHz), P = 2 (field 00), Q = 7, PLLSRC = HSE.
// PLLCFGR = 0x2000'0000 (reserved bit 29, kept from the reset value) | 7 << 24 | 1 << 22 | 168 << 6 | 4
//         = 0x2000'0000 | 0x0700'0000 | 0x0040'0000 | 0x0000'2A00 | 0x4 = 0x2740'2A04.
constexpr std::uint32_t kPllcfgr8MHz = 0x2740'2A04U;
// CFGR: PPRE2 /2 = 100 at [15:13] (0x8000), PPRE1 /4 = 101 at [12:10] (0x1400), SWS = SW = PLL (0x8 | 0x2).
constexpr std::uint32_t kCfgrOnPll = 0x0000'940AU;
// FLASH_ACR: LATENCY 5 (Table 10, 150 < HCLK <= 168 MHz at 2.7-3.6 V), PRFTEN, ICEN, DCEN (bits 8-10).
constexpr std::uint32_t kAcr168MHz = 0x0000'0705U;

TEST(Stm32f4ClockPlan, TheCommonCrystalsGiveTheChipsMaximumClocks) {
  const ClockPlan p = plan_for_hse(8'000'000);
  ASSERT_TRUE(p.valid());
  EXPECT_EQ(p.pll_m, 4U);
  EXPECT_EQ(p.pll_n, 168U);
  EXPECT_EQ(p.sysclk_hz(), 168'000'000U);
  EXPECT_EQ(p.usb_hz(), 48'000'000U);  // USB OTG FS needs exactly 48 MHz
  EXPECT_EQ(p.pclk1_hz(), 42'000'000U);
  EXPECT_EQ(p.pclk2_hz(), 84'000'000U);
  EXPECT_EQ(p.flash_wait_states(), 5U);
  EXPECT_EQ(p.pllcfgr_fields(), kPllcfgr8MHz & ~0x2000'0000U);
  // 25 MHz (an Ethernet board's crystal) is odd in MHz: 1 MHz into the VCO, M = 25, N = 336.
  const ClockPlan q = plan_for_hse(25'000'000);
  ASSERT_TRUE(q.valid());
  EXPECT_EQ(q.pll_m, 25U);
  EXPECT_EQ(q.pll_n, 336U);
  EXPECT_EQ(q.sysclk_hz(), 168'000'000U);
  EXPECT_TRUE(plan_for_hse(12'000'000).valid());
  EXPECT_TRUE(plan_for_hse(26'000'000).valid());
}

TEST(Stm32f4ClockPlan, CrystalsAndDividersOutsideTheManualAreRefused) {
  EXPECT_FALSE(plan_for_hse(12'288'000).valid());  // not a whole number of MHz: M and N by hand
  EXPECT_FALSE(plan_for_hse(2'000'000).valid());   // a crystal below 4 MHz
  EXPECT_FALSE(plan_for_hse(30'000'000).valid());  // a crystal above 26 MHz ...
  EXPECT_TRUE(plan_for_hse(30'000'000, true).valid());  // ... is fine as a bypass clock (up to 50 MHz)
  ClockPlan p = plan_for_hse(8'000'000);
  p.apb1_divider = 2;  // PCLK1 84 MHz > 42 MHz
  EXPECT_FALSE(p.valid());
  p = plan_for_hse(8'000'000);
  p.ahb_divider = 32;  // HPRE has no /32
  EXPECT_FALSE(p.valid());
  p = plan_for_hse(8'000'000);
  p.pll_n = 200;  // VCO 400 MHz, SYSCLK 200 MHz > 168
  EXPECT_FALSE(p.valid());
  p = plan_for_hse(8'000'000);
  p.pll_m = 2;  // VCO input 4 MHz > 2 MHz
  EXPECT_FALSE(p.valid());
}

TEST(Stm32f4ClockPlan, WaitStatesAndPrescalerFieldsFollowTheManualsTables) {
  ClockPlan p = plan_for_hse(8'000'000);
  // Table 10 at 2.7-3.6 V: HCLK 84 MHz -> 2 WS, 42 MHz -> 1 WS, 21 MHz -> 0 WS.
  p.ahb_divider = 2;
  EXPECT_EQ(p.flash_wait_states(), 2U);
  EXPECT_EQ(p.cfgr_prescalers() & 0xF0U, 0x80U);  // HPRE 1000 = /2
  p.ahb_divider = 4;
  EXPECT_EQ(p.flash_wait_states(), 1U);
  p.ahb_divider = 8;
  EXPECT_EQ(p.flash_wait_states(), 0U);
  p.ahb_divider = 64;
  EXPECT_EQ(p.cfgr_prescalers() & 0xF0U, 0xC0U);  // HPRE 1100 = /64 (the code after /16 skips /32)
  p.ahb_divider = 512;
  EXPECT_EQ(p.cfgr_prescalers() & 0xF0U, 0xF0U);  // HPRE 1111 = /512
  p = plan_for_hse(8'000'000);
  p.apb1_divider = 16;
  EXPECT_EQ((p.cfgr_prescalers() >> 10) & 0x7U, 0x7U);  // PPRE1 111 = /16
}

TEST(Stm32f4ClockTree, FromResetItRunsOnThePllWithTheManualsRegisterValues) {
  ChipModel chip;
  EXPECT_EQ(start_clock_tree(chip, test_plan()), ClockStart::kOnPll);
  EXPECT_TRUE(chip.breaches.empty()) << chip.breaches.front();
  EXPECT_EQ(chip.reg.at(cr::kRccPllcfgr), kPllcfgr8MHz);
  EXPECT_EQ(chip.reg.at(cr::kRccCfgr), kCfgrOnPll);
  EXPECT_EQ(chip.reg.at(cr::kFlashAcr), kAcr168MHz);
  EXPECT_EQ(chip.reg.at(cr::kPwrCr), 0x0000'4000U);
  EXPECT_EQ(chip.reg.at(cr::kRccApb1enr), 1U << 28);
  // HSI left on, HSE and PLL on and ready, no bypass: 0x0000'7883 | HSEON, HSERDY (bits 16, 17) | PLLON, PLLRDY (24, 25).
  EXPECT_EQ(chip.reg.at(cr::kRccCr), 0x0303'7883U);
  EXPECT_TRUE(runs_as_planned(ClockStart::kOnPll));
}

TEST(Stm32f4ClockTree, AnExternalClockIsBypassedBeforeTheHseStarts) {
  ChipModel chip;
  EXPECT_EQ(start_clock_tree(chip, plan_for_hse(8'000'000, true).settings()), ClockStart::kOnPll);
  EXPECT_TRUE(chip.breaches.empty()) << chip.breaches.front();
  EXPECT_NE(chip.reg.at(cr::kRccCr) & cr::kCrHseByp, 0U);
}

TEST(Stm32f4ClockTree, ACrystalThatDoesNotStartLeavesTheHsiAndTheHseOff) {
  ChipModel chip;
  chip.crystal_starts = false;
  const ClockSettings plan = test_plan();
  EXPECT_EQ(start_clock_tree(chip, plan), ClockStart::kHseNotReady);
  EXPECT_EQ(chip.sysclk_source(), cr::kSwHsi);
  EXPECT_EQ(chip.reg.at(cr::kRccCr) & cr::kCrHseOn, 0U);
  EXPECT_EQ(chip.reg.at(cr::kRccPllcfgr), 0x2400'3010U);  // untouched
  EXPECT_LE(chip.reads, plan.ready_poll_limit + 20U);     // the wait is bounded
  EXPECT_FALSE(runs_as_planned(ClockStart::kHseNotReady));
}

TEST(Stm32f4ClockTree, APllThatDoesNotLockLeavesTheHsi) {
  ChipModel chip;
  chip.pll_locks = false;
  EXPECT_EQ(start_clock_tree(chip, test_plan()), ClockStart::kPllNotReady);
  EXPECT_EQ(chip.sysclk_source(), cr::kSwHsi);
  EXPECT_TRUE(chip.breaches.empty()) << chip.breaches.front();
}

TEST(Stm32f4ClockTree, FlashThatRefusesTheWaitStatesStopsTheSequenceBeforeTheClockRises) {
  ChipModel chip;
  chip.flash_takes_latency = false;
  EXPECT_EQ(start_clock_tree(chip, test_plan()), ClockStart::kFlashLatencyRefused);
  EXPECT_EQ(chip.sysclk_source(), cr::kSwHsi);
  EXPECT_EQ(chip.reg.at(cr::kRccCr) & cr::kCrPllOn, 0U);
  EXPECT_TRUE(chip.breaches.empty()) << chip.breaches.front();
}

TEST(Stm32f4ClockTree, ABootLoadersRunningPllIsLeftForTheHsiBeforeItIsReconfigured) {
  ChipModel chip;
  // A boot loader left SYSCLK on its own PLL (M = 8, N = 336: 0x0740'5408 with PLLSRC = HSE), 5 wait states, and
  // the PLLI2S running (bits 26, 27).
  chip.reg.at(cr::kRccCr) = 0x0F03'7883U;
  chip.reg.at(cr::kRccPllcfgr) = 0x2740'5408U;
  chip.reg.at(cr::kRccCfgr) = kCfgrOnPll;
  chip.reg.at(cr::kFlashAcr) = kAcr168MHz;
  chip.reg.at(cr::kRccApb1enr) = 1U << 28;
  EXPECT_EQ(start_clock_tree(chip, test_plan()), ClockStart::kOnPll);
  EXPECT_TRUE(chip.breaches.empty()) << chip.breaches.front();
  EXPECT_EQ(chip.reg.at(cr::kRccPllcfgr), kPllcfgr8MHz);
  EXPECT_EQ(chip.reg.at(cr::kRccCfgr), kCfgrOnPll);
}

TEST(Stm32f4ClockTree, ARunningCrystalIsStoppedBeforeTheBypassIsSetAndStartedAgain) {
  ChipModel chip;
  chip.reg.at(cr::kRccCr) = 0x0003'7883U;  // HSEON, HSERDY: a crystal already running (a boot loader's)
  EXPECT_EQ(start_clock_tree(chip, plan_for_hse(8'000'000, true).settings()), ClockStart::kOnPll);
  EXPECT_TRUE(chip.breaches.empty()) << chip.breaches.front();
  EXPECT_NE(chip.reg.at(cr::kRccCr) & cr::kCrHseByp, 0U);
  ChipModel stuck;
  stuck.reg.at(cr::kRccCr) = 0x0003'7883U;
  stuck.crystal_stops = false;  // HSERDY stays set
  EXPECT_EQ(start_clock_tree(stuck, plan_for_hse(8'000'000, true).settings()), ClockStart::kHseDidNotStop);
  EXPECT_TRUE(stuck.breaches.empty()) << stuck.breaches.front();
  EXPECT_EQ(stuck.reg.at(cr::kRccCr) & cr::kCrHseByp, 0U);  // not written while the HSE runs
}

TEST(Stm32f4ClockTree, VoltageScale1IsSetWhereABootLoaderLoweredIt) {
  ChipModel chip;
  chip.reg.at(cr::kPwrCr) = 0;  // scale 2
  EXPECT_EQ(start_clock_tree(chip, test_plan()), ClockStart::kOnPll);
  EXPECT_EQ(chip.reg.at(cr::kPwrCr), 0x0000'4000U);
}

TEST(Stm32f4ClockTree, APllConfigurationThatDoesNotReadBackStopsBeforeThePllStarts) {
  ChipModel chip;
  chip.pllcfgr_writable = false;
  EXPECT_EQ(start_clock_tree(chip, test_plan()), ClockStart::kPllConfigRefused);
  EXPECT_EQ(chip.reg.at(cr::kRccCr) & cr::kCrPllOn, 0U);
  EXPECT_EQ(chip.sysclk_source(), cr::kSwHsi);
}

TEST(Stm32f4ClockTree, WithoutAnRccItTakesTheEmulatorsClockAndWritesNothing) {
  ChipModel chip;
  chip.no_rcc = true;  // QEMU 7.2's netduinoplus2: the RCC is an unimplemented-device stub that reads 0
  EXPECT_EQ(start_clock_tree(chip, test_plan()), ClockStart::kFixedByEmulator);
  EXPECT_TRUE(chip.writes.empty());
  EXPECT_TRUE(runs_as_planned(ClockStart::kFixedByEmulator));
}

TEST(Stm32f4ClockTree, AnInvalidPlanWritesNothing) {
  ChipModel chip;
  EXPECT_EQ(start_clock_tree(chip, plan_for_hse(12'288'000).settings()), ClockStart::kInvalidPlan);
  EXPECT_TRUE(chip.writes.empty());
  EXPECT_STREQ(to_string(ClockStart::kInvalidPlan), "the clock plan breaks a rule of RM0090");
}

TEST(Stm32f4UsartPins, Usart1OnPa9AndPa10IsAlternateFunction7) {
  ChipModel chip;
  route_usart_pins(chip, kUsart1PinsPA9PA10);
  EXPECT_EQ(chip.reg.at(kRccAhb1enr), 0x0010'0001U);  // GPIOAEN, CCMDATARAMEN kept
  // MODER: 10 at [19:18] (PA9) and [21:20] (PA10) -> 0x000A'0000 beside the debug pins' 0xA800'0000.
  EXPECT_EQ(chip.reg.at(kGpioA + pin_registers::kModer), 0xA828'0000U);
  // AFRH: 7 in the nibbles of pins 9 and 10 ([7:4], [11:8]).
  EXPECT_EQ(chip.reg.at(kGpioA + pin_registers::kAfrh), 0x0000'0770U);
  EXPECT_EQ(chip.reg.at(kGpioA + pin_registers::kAfrl), 0U);
  // Pull-up (01) and medium speed (01) at [19:18] and [21:20]: 0x0014'0000 on each reset value.
  EXPECT_EQ(chip.reg.at(kGpioA + pin_registers::kPupdr), 0x6414'0000U);
  EXPECT_EQ(chip.reg.at(kGpioA + pin_registers::kOspeedr), 0x0C14'0000U);
  EXPECT_EQ(chip.reg.at(kGpioA + pin_registers::kOtyper), 0U);
}

// Whether, in the writes, every pin's alternate function was in place before its mode became "alternate function".
bool function_before_mode(const ChipModel& chip, const UsartPins& pins) {
  for (const std::uint32_t pin : {pins.tx_pin, pins.rx_pin}) {
    const std::uintptr_t afr = kGpioA + (pin < 8 ? pin_registers::kAfrl : pin_registers::kAfrh);
    bool function_set = false;
    for (const auto& [address, value] : chip.writes) {
      if (address == afr && ((value >> (4 * (pin % 8))) & 0xFU) == pins.alternate_function) function_set = true;
      if (address == kGpioA + pin_registers::kModer && ((value >> (2 * pin)) & 0x3U) == 2U && !function_set) {
        return false;
      }
    }
  }
  return true;
}

TEST(Stm32f4UsartPins, Usart2OnPa2AndPa3IsAlternateFunction7AndTheModeComesLast) {
  ChipModel chip;
  route_usart_pins(chip, kUsart2PinsPA2PA3);
  // MODER: 10 at [5:4] and [7:6] -> 0xA0; AFRL: 7 in the nibbles of pins 2 and 3 ([11:8], [15:12]).
  EXPECT_EQ(chip.reg.at(kGpioA + pin_registers::kModer), 0xA800'00A0U);
  EXPECT_EQ(chip.reg.at(kGpioA + pin_registers::kAfrl), 0x0000'7700U);
  EXPECT_TRUE(function_before_mode(chip, kUsart2PinsPA2PA3));
  ChipModel usart1;
  route_usart_pins(usart1, kUsart1PinsPA9PA10);
  EXPECT_TRUE(function_before_mode(usart1, kUsart1PinsPA9PA10));
}

}  // namespace
