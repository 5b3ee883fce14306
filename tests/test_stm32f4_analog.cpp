// The STM32F405 analog board's sequences (hal/stm32f4/include/lashid/hal/stm32f4/analog.hpp), run on the PC against
// a model of the registers they touch: QEMU has no DAC, and its ADC never sets EOC. Expected register values are
// derived by hand from RM0090 (rev 19) field layouts, each written out beside its derivation; codes and volts from
// the converters' transfer functions (DAC_OUT = Vref x DOR / 4095, 14.3.5; ADC code = 4095 x Vin / Vref, 13.1).
// The model enforces the manual's rules that the sequences could break and records any breach.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <vector>

#include <gtest/gtest.h>

#include "lashid/hal/stm32f4/analog.hpp"

namespace {

using namespace lashid::hal;
using namespace lashid::hal::stm32f4;
namespace ar = analog_registers;

// RCC enables, GPIOA-C MODER, the DAC and ADC1 as the chip has them after reset (reset values: RM0090 7.3.10,
// 7.3.13, 7.3.14, 8.4.1, 14.5, 13.13). A conversion ends `eoc_after_reads` reads of SR after SWSTART, with the
// code of `input_volts`; a DHR write reaches DOR1.
class AnalogChipModel {
 public:
  double input_volts = 0.0, vref = 3.3;
  int eoc_after_reads = 3;
  bool converts = true;   // false: EOC never comes (a dead ADC clock)
  bool qemu = false;      // QEMU's ADC: no EOC; DR, while SWSTART is set, answers 7 above its last value
  bool dac_wired_to_adc = false;  // PA4 wired to the ADC's pin: the DAC's output is the input, at once
  std::uint32_t reads = 0, conversions = 0;
  std::vector<const char*> breaches;
  std::map<std::uintptr_t, std::uint32_t> reg{
      {ar::kRccAhb1enr, 0x0010'0000U},  // CCMDATARAMEN
      {ar::kRccApb1enr, 0x0000'0000U},
      {ar::kRccApb2enr, 0x0000'0000U},
      {ar::kGpioA + ar::kModer, 0xA800'0000U},  // the debug pins PA13-PA15
      {ar::kGpioB + ar::kModer, 0x0000'0280U},  // PB3, PB4 (debug)
      {ar::kGpioC + ar::kModer, 0x0000'0000U},
      {ar::kDacCr, 0x0000'0000U},
      {ar::kDacDhr12r1, 0U},
      {ar::kDacDor1, 0U},
      {ar::kAdcSr, 0U},
      {ar::kAdcCr1, 0U},
      {ar::kAdcCr2, 0U},
      {ar::kAdcSmpr1, 0U},
      {ar::kAdcSmpr2, 0U},
      {ar::kAdcSqr1, 0U},
      {ar::kAdcSqr3, 0U},
      {ar::kAdcDr, 0U},
      {ar::kAdcCcr, 0U},
  };

  std::uint32_t read(std::uintptr_t address) {
    ++reads;
    ++reads_since_adon_;
    if (address == ar::kAdcSr && pending_ > 0 && --pending_ == 0) {
      reg.at(ar::kAdcSr) |= ar::kSrEoc;
      reg.at(ar::kAdcDr) = code_of(input_volts);
    }
    if (address == ar::kAdcDr) {
      if (qemu) {
        if ((reg.at(ar::kAdcCr2) & (ar::kCr2Adon | ar::kCr2Swstart)) != (ar::kCr2Adon | ar::kCr2Swstart)) return 0;
        reg.at(ar::kAdcCr2) &= ~ar::kCr2Swstart;
        reg.at(ar::kAdcDr) = (reg.at(ar::kAdcDr) + 7U) & 0xFFFU;
      }
      reg.at(ar::kAdcSr) &= ~ar::kSrEoc;  // reading DR clears EOC (13.13.1)
    }
    return reg.at(address);
  }

  void write(std::uintptr_t address, std::uint32_t value) {
    std::uint32_t& r = reg.at(address);
    const auto clocked = [&](std::uintptr_t enable, std::uint32_t bit) { return (reg.at(enable) & bit) != 0; };
    if (address >= ar::kGpioA && address < ar::kGpioC + 0x400) {
      const std::uint32_t port_bit = 1U << ((address - ar::kGpioA) / 0x400);
      if (!clocked(ar::kRccAhb1enr, port_bit)) breaches.push_back("GPIO written with its port's clock off");
    }
    if (address >= ar::kDac && address < ar::kDac + 0x400 && !clocked(ar::kRccApb1enr, ar::kApb1enrDacEn)) {
      breaches.push_back("DAC written with its clock off");
    }
    if (address >= ar::kAdc1 && address < ar::kAdc1 + 0x400 && !clocked(ar::kRccApb2enr, ar::kApb2enrAdc1En)) {
      breaches.push_back("ADC written with its clock off");
    }
    if (address == ar::kAdcCr2) {
      const bool was_on = (r & ar::kCr2Adon) != 0;
      if ((value & ar::kCr2Swstart) != 0) {
        // 13.3.1: ADON set while the ADC is off only powers it up; a conversion needs it on, and stable (t_STAB
        // 3 us = 504 cycles at 168 MHz, DS8626 Table 66; each register read takes at least one cycle).
        if (!was_on) breaches.push_back("SWSTART with the ADC off");
        if (reads_since_adon_ < 504) breaches.push_back("SWSTART within t_STAB of ADON");
        ++conversions;
        if (converts && !qemu) pending_ = eoc_after_reads;
      }
      if (!was_on && (value & ar::kCr2Adon) != 0) reads_since_adon_ = 0;
      r = value;
      if (!qemu) r &= ~ar::kCr2Swstart;  // the chip clears SWSTART when the conversion starts
      return;
    }
    if (address == ar::kAdcSr) {
      r &= value;  // rc_w0
      return;
    }
    if (address == ar::kDacDhr12r1) {
      r = value & 0xFFFU;
      if ((reg.at(ar::kDacCr) & ar::kDacCrEn1) != 0) reg.at(ar::kDacDor1) = r;
      if (dac_wired_to_adc) input_volts = vref * reg.at(ar::kDacDor1) / 4095.0;
      return;
    }
    r = value;
  }

  std::uint32_t code_of(double volts) const {
    const double code = std::round(4095.0 * volts / vref);
    return static_cast<std::uint32_t>(std::clamp(code, 0.0, 4095.0));
  }

 private:
  int pending_ = 0;
  std::uint32_t reads_since_adon_ = 0;
};
static_assert(RegisterBus<AnalogChipModel>);

TEST(Stm32f4AnalogPlan, TheRulesOfTheChipAreChecked) {
  EXPECT_TRUE(AnalogPlan{}.valid());
  AnalogPlan plan;
  plan.adc_channel = 4;  // PA4 is DAC_OUT1
  EXPECT_FALSE(plan.valid());
  plan.adc_channel = 16;  // the temperature sensor, no pin
  EXPECT_FALSE(plan.valid());
  plan = AnalogPlan{};
  plan.vref_volts = 5.0F;  // above VDDA's 3.6 V
  EXPECT_FALSE(plan.valid());
  plan.vref_volts = 2.0F;  // below 2.4 V the 21 MHz ADC clock is beyond the chip's 18 MHz
  plan.actuator_rest = 1.0F;
  EXPECT_FALSE(plan.valid());
  plan = AnalogPlan{};
  plan.actuator_rest = 3.2F;  // beyond the buffered output's 3.1 V
  EXPECT_FALSE(plan.valid());
  EXPECT_FLOAT_EQ(plan.with_rest_at_middle().actuator_rest, 1.65F);
  EXPECT_TRUE(plan.with_rest_at_middle().valid());
  plan = AnalogPlan{};
  plan.sensor.gain = 0.0F;
  EXPECT_FALSE(plan.valid());
  plan = AnalogPlan{};
  plan.actuator.offset = std::nanf("");
  EXPECT_FALSE(plan.valid());
  // DS8626 Table 7: IN1 = PA1, IN9 = PB1, IN11 = PC1.
  EXPECT_EQ(adc_channel_pin(1).gpio_base, ar::kGpioA);
  EXPECT_EQ(adc_channel_pin(9).gpio_base, ar::kGpioB);
  EXPECT_EQ(adc_channel_pin(9).pin, 1U);
  EXPECT_EQ(adc_channel_pin(11).gpio_base, ar::kGpioC);
  EXPECT_EQ(adc_channel_pin(11).pin, 1U);
  EXPECT_EQ(adc_channel_pin(11).rcc_ahb1enr_bit, 1U << 2);
}

TEST(Stm32f4Dac, StartsChannel1OnPa4WithItsBufferAndNoTriggerAtTheRestValue) {
  AnalogChipModel chip;
  chip.reg.at(ar::kDacCr) = 0x0001'0000U;  // channel 2 already on (EN2): kept
  AnalogPlan plan;
  plan.vref_volts = 2.5F;
  plan.actuator_rest = 0.625F;  // 4095 x 0.625 / 2.5 = 1023.75 -> 1024
  start_dac(chip, plan);
  EXPECT_TRUE(chip.breaches.empty()) << chip.breaches.front();
  // MODER4 [9:8] = 11 (analog): 0xA800'0000 | 0x300; the debug pins kept.
  EXPECT_EQ(chip.reg.at(ar::kGpioA + ar::kModer), 0xA800'0300U);
  EXPECT_EQ(chip.reg.at(ar::kRccApb1enr), 1U << 29);  // DACEN
  // DAC_CR: EN1 (bit 0), BOFF1 = 0 (buffer on), TEN1 = 0; EN2 (bit 16) kept.
  EXPECT_EQ(chip.reg.at(ar::kDacCr), 0x0001'0001U);
  EXPECT_EQ(chip.reg.at(ar::kDacDor1), 1024U);  // the rest value until the first command
}

TEST(Stm32f4Dac, TheDesignsUnitsBecomeTheCodeOfTheirVoltsAndNothingOutsideTheRangeIsWritten) {
  AnalogChipModel chip;
  // v = -2.5 + 2 x (volts at PA4), Vref 2.5 V: the buffered output's 0.2-2.3 V is v in [-2.1, 2.1].
  AnalogPlan plan;
  plan.vref_volts = 2.5F;
  plan.actuator = {-2.5F, 2.0F};
  plan.actuator_rest = 0.0F;
  ASSERT_TRUE(plan.valid());
  start_dac(chip, plan);
  EXPECT_FLOAT_EQ(plan.actuator_low(), -2.1F);
  EXPECT_FLOAT_EQ(plan.actuator_high(), 2.1F);
  // v = 1.25: 1.875 V, 4095 x 1.875 / 2.5 = 3071.25 -> 3071.
  EXPECT_EQ(write_dac(chip, plan, 1.25F), Status::kOk);
  EXPECT_EQ(chip.reg.at(ar::kDacDor1), 3071U);
  // v = -1.0: 0.75 V, 4095 x 0.3 = 1228.5 -> 1229 (half up).
  EXPECT_EQ(write_dac(chip, plan, -1.0F), Status::kOk);
  EXPECT_EQ(chip.reg.at(ar::kDacDor1), 1229U);
  // v = -2.1: 0.2 V, 4095 x 0.08 = 327.6 -> 328; v = 2.1: 2.3 V, 4095 x 0.92 = 3767.4 -> 3767.
  EXPECT_EQ(write_dac(chip, plan, -2.1F), Status::kOk);
  EXPECT_EQ(chip.reg.at(ar::kDacDor1), 328U);
  EXPECT_EQ(write_dac(chip, plan, 2.1F), Status::kOk);
  EXPECT_EQ(chip.reg.at(ar::kDacDor1), 3767U);
  // Within half a code (2 x 0.5 x 2.5 / 4095 = 0.00061 in v) of the top: accepted (2.30025 V: 3767.8 -> 3768).
  EXPECT_EQ(write_dac(chip, plan, 2.1005F), Status::kOk);
  EXPECT_EQ(chip.reg.at(ar::kDacDor1), 3768U);
  // Beyond what the buffered output reaches, NaN and infinity: refused, the last value stays on the pin.
  for (const float v : {2.11F, -2.11F, 2.5F, -2.5F, std::nanf(""), INFINITY}) {
    EXPECT_EQ(write_dac(chip, plan, v), Status::kOutOfRange) << v;
    EXPECT_EQ(chip.reg.at(ar::kDacDor1), 3768U) << v;
  }
}

TEST(Stm32f4Dac, AnInvertingStageHasItsRangeTheRightWayRound) {
  // v = 3.3 - volts at PA4 (gain -1), Vref 3.3 V: 0.2-3.1 V is v in [0.2, 3.1].
  AnalogPlan plan;
  plan.actuator = {3.3F, -1.0F};
  EXPECT_FLOAT_EQ(plan.actuator_low(), 0.2F);
  EXPECT_FLOAT_EQ(plan.actuator_high(), 3.1F);
  EXPECT_TRUE(plan.valid());  // the rest 1.65 lies inside
  AnalogChipModel chip;
  start_dac(chip, plan);
  // v = 1.0: 2.3 V, 4095 x 2.3 / 3.3 = 2854.09 -> 2854.
  EXPECT_EQ(write_dac(chip, plan, 1.0F), Status::kOk);
  EXPECT_EQ(chip.reg.at(ar::kDacDor1), 2854U);
  EXPECT_EQ(write_dac(chip, plan, 3.2F), Status::kOutOfRange);  // 0.1 V
}

TEST(Stm32f4Adc, StartsOneTwelveBitConversionOfItsChannelAtPclk2Over4) {
  for (const std::uint32_t channel : {1U, 11U}) {
    AnalogChipModel chip;
    AnalogPlan plan;
    plan.adc_channel = channel;
    start_adc(chip, plan);
    EXPECT_TRUE(chip.breaches.empty()) << chip.breaches.front();
    if (channel == 1) {
      EXPECT_EQ(chip.reg.at(ar::kGpioA + ar::kModer), 0xA800'000CU);  // MODER1 [3:2] = 11
      EXPECT_EQ(chip.reg.at(ar::kAdcSmpr2), 0x20U);                    // SMP1 [5:3] = 100 (84 cycles)
      EXPECT_EQ(chip.reg.at(ar::kAdcSmpr1), 0U);
    } else {
      EXPECT_EQ(chip.reg.at(ar::kRccAhb1enr) & 0x7U, 1U << 2);       // GPIOCEN only
      EXPECT_EQ(chip.reg.at(ar::kGpioC + ar::kModer), 0x0000'000CU);  // PC1: MODER1 [3:2] = 11
      EXPECT_EQ(chip.reg.at(ar::kAdcSmpr1), 0x20U);                   // SMP11 is SMPR1 [5:3]
      EXPECT_EQ(chip.reg.at(ar::kAdcSmpr2), 0U);
    }
    EXPECT_EQ(chip.reg.at(ar::kRccApb2enr), 1U << 8);  // ADC1EN
    EXPECT_EQ(chip.reg.at(ar::kAdcCcr), 0x0001'0000U);  // ADCPRE = 01: PCLK2 / 4
    EXPECT_EQ(chip.reg.at(ar::kAdcCr1), 0U);            // RES = 00: 12 bits
    EXPECT_EQ(chip.reg.at(ar::kAdcSqr1), 0U);           // L = 0: one conversion
    EXPECT_EQ(chip.reg.at(ar::kAdcSqr3), channel);      // SQ1
    EXPECT_EQ(chip.reg.at(ar::kAdcCr2), 1U);            // ADON only: single, right-aligned
  }
}

TEST(Stm32f4Adc, AConversionGivesTheSensorsUnitsAndAClippedCodeIsOutOfRange) {
  AnalogChipModel chip;
  AnalogPlan plan;  // Vref 3.3 V
  plan.sensor = {10.0F, -4.0F};  // y = 10 - 4 x (volts at PA1)
  start_adc(chip, plan);
  chip.input_volts = 1.0;  // code round(4095 / 3.3) = round(1240.9) = 1241; y = 10 - 4 x 3.3 x 1241 / 4095
  float y = 0;
  EXPECT_EQ(read_adc(chip, plan, y), Status::kOk);
  EXPECT_NEAR(y, 10.0 - 4.0 * 3.3 * 1241.0 / 4095.0, 1e-5);
  EXPECT_EQ(chip.conversions, 1U);
  EXPECT_EQ(chip.reg.at(ar::kAdcSr) & ar::kSrEoc, 0U);  // DR read: EOC cleared for the next sample
  chip.input_volts = 3.5;  // above Vref: code 4095, y = 10 - 4 x 3.3 = -3.2
  EXPECT_EQ(read_adc(chip, plan, y), Status::kOutOfRange);
  EXPECT_NEAR(y, -3.2, 1e-5);
  chip.input_volts = -0.2;  // below ground: code 0
  EXPECT_EQ(read_adc(chip, plan, y), Status::kOutOfRange);
  EXPECT_TRUE(chip.breaches.empty()) << chip.breaches.front();
}

TEST(Stm32f4Adc, AConversionThatNeverEndsIsATimeoutAfterABoundedWait) {
  AnalogChipModel chip;
  chip.converts = false;
  AnalogPlan plan;
  start_adc(chip, plan);
  const std::uint32_t before = chip.reads;
  float y = 123.0F;
  EXPECT_EQ(read_adc(chip, plan, y), Status::kTimeout);
  EXPECT_EQ(y, 123.0F);  // untouched
  EXPECT_LE(chip.reads - before, ar::kConversionPolls + 2);
}

TEST(Stm32f4Adc, UnderQemuTheSawtoothOfItsAdcIsReadWithoutWaitingForEoc) {
  AnalogChipModel chip;
  chip.qemu = true;
  AnalogPlan plan;  // y = volts at the pin
  start_adc(chip, plan);
  float y = 0;
  // Waiting for EOC, which QEMU never sets: a timeout.
  EXPECT_EQ(read_adc(chip, plan, y), Status::kTimeout);
  // Emulated: DR answers 7, 14, 21 (the timed-out attempt never read DR).
  for (const std::uint32_t code : {7U, 14U, 21U}) {
    EXPECT_EQ(read_adc(chip, plan, y, true), Status::kOk);
    EXPECT_NEAR(y, 3.3 * code / 4095.0, 1e-6) << code;
  }
}

// A plant that is all feedthrough (PA4 wired to the ADC's pin, the DAC's output at once): each sample's y is the
// previous sample's v, never its own, because y(t) is converted before v(t) is written. Volts both ways (the default
// plan); one code of the DAC and of the ADC is 3.3 / 4095 = 0.8 mV each.
TEST(Stm32f4AnalogTick, TheOutputIsConvertedBeforeTheCommandIsWritten) {
  AnalogChipModel chip;
  chip.dac_wired_to_adc = true;
  AnalogPlan plan;
  start_dac(chip, plan);
  start_adc(chip, plan);
  float y = 0;
  const float v[] = {1.0F, 2.5F, 0.5F};
  TickStatus s = sample_then_actuate(chip, plan, v[0], y);
  EXPECT_EQ(s.measured, Status::kOk);
  EXPECT_EQ(s.actuated, Status::kOk);
  for (int k = 1; k < 3; ++k) {
    s = sample_then_actuate(chip, plan, v[k], y);
    EXPECT_EQ(s.measured, Status::kOk);
    EXPECT_EQ(s.actuated, Status::kOk);
    EXPECT_NEAR(y, v[k - 1], 2 * 3.3 / 4095.0) << k;  // the previous v, to a code of each converter
  }
  // A command outside the DAC's range is not written; the conversion before it still is this sample's y.
  s = sample_then_actuate(chip, plan, 3.25F, y);
  EXPECT_EQ(s.actuated, Status::kOutOfRange);
  EXPECT_EQ(s.measured, Status::kOk);
  EXPECT_NEAR(y, v[2], 2 * 3.3 / 4095.0);
  EXPECT_TRUE(chip.breaches.empty()) << chip.breaches.front();
}

}  // namespace
