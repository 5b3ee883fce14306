// The STM32F405's analog actuator and sensor: DAC channel 1 on PA4 drives the actuator's command v, ADC1 samples
// the plant's output y on one channel, once per sample (software start, single conversion, polled). Written from
// RM0090 (rev 19): 14 (DAC), 13 (ADC), 8.3.12 (analog pin mode), 7.3.10/7.3.13/7.3.14 (RCC clock enables); the
// ADC channels' pins from the STM32F405 datasheet DS8626, Table 7.
//
//   AnalogPlan        the channel, the reference voltage, the two affine scalings between the design's units
//                     and the pins' volts, and the actuator's rest (valid(): the checks the image static_asserts)
//   start_dac         PA4 analog, the DAC clocked, channel 1 on with its output buffer at the rest value, no trigger
//   start_adc         the channel's pin analog, ADC1 clocked at PCLK2 / 4, 12 bits, one conversion of the channel
//   write_dac         v in design units -> DHR12R1, or kOutOfRange (not written) outside what the buffered output
//                     reaches (0.2 V to Vref - 0.2 V)
//   read_adc          one conversion: EOC awaited (bounded), a clipped code is kOutOfRange, a conversion that does
//                     not finish is kTimeout
//   sample_then_actuate  one sample instant: y(t) converted, then v(t) written (no path from v(t) into y(t))
//
// QEMU 7.2's netduinoplus2 has no DAC (writes ignored) and an ADC that never sets SR.EOC: its DR answers, while
// SWSTART is set, a code 7 above the last one (a sawtooth modulo 4096). With `emulated` (the clock tree found no
// RCC, ClockStart::kFixedByEmulator) read_adc reads DR without waiting for EOC; the chip always waits. Freestanding,
// no heap; on any RegisterBus, so that the sequences are tested on the PC (tests/test_stm32f4_analog.cpp).
#pragma once

#include <algorithm>
#include <cstdint>

#include "lashid/hal/status.hpp"
#include "lashid/hal/stm32f4/clock_tree.hpp"
#include "lashid/hal/stm32f4/register_bus.hpp"
#include "lashid/hal/stm32f4/usart_pins.hpp"

namespace lashid::hal::stm32f4 {

namespace analog_registers {
// RCC clock enables (7.3.10, 7.3.13, 7.3.14): AHB1ENR (GPIOAEN [0], GPIOBEN [1], GPIOCEN [2]) and APB1ENR as the pins
// and the clock tree name them, APB2ENR here
using pin_registers::kRccAhb1enr;
using clock_registers::kRccApb1enr;
inline constexpr std::uintptr_t kRccApb2enr = 0x4002'3844;
inline constexpr std::uint32_t kApb1enrDacEn = 1U << 29;
inline constexpr std::uint32_t kApb2enrAdc1En = 1U << 8;
// GPIO ports A, B, C (RM0090 2.3, Table 1: every 0x400 from GPIOA) and MODER (8.4.1): 11 = analog
using pin_registers::kGpioA;
using pin_registers::kModer;
inline constexpr std::uintptr_t kGpioB = kGpioA + 0x400;
inline constexpr std::uintptr_t kGpioC = kGpioA + 0x800;
inline constexpr std::uint32_t kModeAnalog = 3U;
// DAC (14.5; base 0x40007400): CR EN1 [0], BOFF1 [1] (0 = output buffer on), TEN1 [2] (0 = DHR to DOR one APB1
// cycle after the write; the pin then settles within t_SETTLING, 3 us typical, 6 us max: DS8626); DHR12R1 [11:0];
// DOR1 [11:0]
inline constexpr std::uintptr_t kDac = 0x4000'7400;
inline constexpr std::uintptr_t kDacCr = kDac + 0x00;
inline constexpr std::uintptr_t kDacDhr12r1 = kDac + 0x08;
inline constexpr std::uintptr_t kDacDor1 = kDac + 0x2C;
inline constexpr std::uint32_t kDacCrEn1 = 1U << 0;
inline constexpr std::uint32_t kDacCrChannel1Mask = 0xFFFFU;  // channel 1's half of DAC_CR (EN1 .. DMAUDRIE1)
inline constexpr std::uint32_t kDacDacPin = 4;                // DAC_OUT1 is PA4 (DS8626 Table 7)
/// With its buffer on, DAC_OUT swings from 0.2 V to VDDA - 0.2 V (DS8626, DAC characteristics).
inline constexpr float kDacBufferMarginVolts = 0.2F;
// ADC1 (13.13; base 0x40012000) and the common registers (13.13.16; base 0x40012300)
inline constexpr std::uintptr_t kAdc1 = 0x4001'2000;
inline constexpr std::uintptr_t kAdcSr = kAdc1 + 0x00;     // EOC [1], STRT [4]
inline constexpr std::uintptr_t kAdcCr1 = kAdc1 + 0x04;    // RES [25:24] (00 = 12 bits), SCAN [8]
inline constexpr std::uintptr_t kAdcCr2 = kAdc1 + 0x08;    // ADON [0], CONT [1], EOCS [10], ALIGN [11], SWSTART [30]
inline constexpr std::uintptr_t kAdcSmpr1 = kAdc1 + 0x0C;  // SMP10..SMP18, 3 bits each
inline constexpr std::uintptr_t kAdcSmpr2 = kAdc1 + 0x10;  // SMP0..SMP9, 3 bits each
inline constexpr std::uintptr_t kAdcSqr1 = kAdc1 + 0x2C;   // L [23:20]: conversions - 1
inline constexpr std::uintptr_t kAdcSqr3 = kAdc1 + 0x34;   // SQ1 [4:0]
inline constexpr std::uintptr_t kAdcDr = kAdc1 + 0x4C;
inline constexpr std::uintptr_t kAdcCcr = 0x4001'2304;     // ADCPRE [17:16]: PCLK2 / 2, 4, 6, 8
inline constexpr std::uint32_t kSrEoc = 1U << 1;
inline constexpr std::uint32_t kCr2Adon = 1U << 0;
inline constexpr std::uint32_t kCr2Swstart = 1U << 30;
inline constexpr std::uint32_t kCcrAdcpreMask = 3U << 16;
/// PCLK2 / 4: 21 MHz from the plan's 84 MHz, within the 36 MHz ADCCLK maximum at VDDA 2.4-3.6 V (DS8626 Table 66;
/// 18 MHz below 2.4 V, which AnalogPlan::valid() excludes).
inline constexpr std::uint32_t kCcrAdcpreDiv4 = 1U << 16;
/// 84 ADC cycles of sampling (SMP = 100): 4 us at 21 MHz. DS8626's equation 1 (12 bits, C_ADC 4 pF, R_ADC 6 kOhm)
/// then allows a source of about 96 kOhm, beyond the datasheet's 50 kOhm R_AIN maximum; a conversion takes
/// 84 + 12 cycles, 4.6 us, far inside a 1 ms sample.
inline constexpr std::uint32_t kSampleTime84Cycles = 4U;
inline constexpr std::uint32_t kFullScaleCode = 4095U;
/// t_STAB, the ADC's power-up time (DS8626 Table 66: 3 us max), in register reads (each at least one 168 MHz
/// cycle, 6 ns): 3 us is at most 504 reads; 1,000 leave margin.
inline constexpr std::uint32_t kStabilisationReads = 1000;
/// EOC after SWSTART: 96 ADC cycles = 768 CPU cycles at 168 MHz; a read is at least one cycle. 100,000 reads
/// (>= 0.6 ms) is a conversion that will not finish, not a slow one.
inline constexpr std::uint32_t kConversionPolls = 100'000;
}  // namespace analog_registers

/// A GPIO pin: its port's registers and the RCC_AHB1ENR bit that clocks the port.
struct AnalogPin {
  std::uintptr_t gpio_base = 0;
  std::uint32_t rcc_ahb1enr_bit = 0;
  std::uint32_t pin = 0;
};

/// ADC123_IN0..IN15's pins (DS8626 Table 7): PA0-PA7, PB0-PB1, PC0-PC5.
constexpr AnalogPin adc_channel_pin(std::uint32_t channel) {
  using namespace analog_registers;
  if (channel < 8) return {kGpioA, 1U << 0, channel};
  if (channel < 10) return {kGpioB, 1U << 1, channel - 8};
  return {kGpioC, 1U << 2, channel - 10};
}

/// physical = offset + gain * (volts at the pin): the signal conditioning between the design's units and the pin.
struct AnalogScale {
  float offset = 0.0F;
  float gain = 1.0F;
  constexpr bool valid() const { return offset - offset == 0.0F && gain - gain == 0.0F && gain != 0.0F; }
};

/// The analog half of a board: which ADC channel reads y, the reference voltage of both converters (V_REF+, taken
/// as VDDA: boards without a separate reference tie them), the scalings of v (DAC) and y (ADC), and the command the
/// actuator rests at before a run and after it.
struct AnalogPlan {
  std::uint32_t adc_channel = 1;  ///< ADC123_IN1, PA1
  float vref_volts = 3.3F;
  AnalogScale actuator;           ///< v = offset + gain * DAC_OUT1 volts
  AnalogScale sensor;             ///< y = offset + gain * ADC input volts
  float actuator_rest = 1.65F;    ///< v while no run drives it (design units); with_rest_at_middle() for the middle

  /// What the buffered output reaches on the pin.
  static constexpr float kLowestVolts = analog_registers::kDacBufferMarginVolts;
  constexpr float highest_volts() const { return vref_volts - analog_registers::kDacBufferMarginVolts; }
  /// v at `volts` on the pin.
  constexpr float actuator_at(float volts) const { return actuator.offset + actuator.gain * volts; }
  /// v's range: what the buffered output reaches, 0.2 V to Vref - 0.2 V, in the design's units (either way round: an
  /// inverting stage has a negative gain).
  constexpr float actuator_low() const { return std::min(actuator_at(kLowestVolts), actuator_at(highest_volts())); }
  constexpr float actuator_high() const { return std::max(actuator_at(kLowestVolts), actuator_at(highest_volts())); }
  /// The same plan resting at the middle of the actuator's range.
  constexpr AnalogPlan with_rest_at_middle() const {
    AnalogPlan p = *this;
    p.actuator_rest = 0.5F * (actuator_low() + actuator_high());
    return p;
  }

  /// The rules the image static_asserts: a channel with a pin (IN0..IN15) that is not the DAC's own PA4; a reference
  /// within 2.4-3.6 V (VDDA's range for the 21 MHz ADC clock, DS8626 Table 66); scalings finite with a non-zero
  /// gain; a rest within the actuator's range.
  constexpr bool valid() const {
    return adc_channel <= 15 && adc_channel != analog_registers::kDacDacPin && vref_volts >= 2.4F &&
           vref_volts <= 3.6F && actuator.valid() && sensor.valid() && actuator_rest >= actuator_low() &&
           actuator_rest <= actuator_high();
  }
  /// y for an ADC code (0..4095: code / 4095 of Vref).
  constexpr float sensor_value(std::uint32_t code) const {
    return sensor.offset + sensor.gain * (vref_volts * static_cast<float>(code) / 4095.0F);
  }
  /// The DAC code for v, rounded to the nearest (DAC_OUT1 = Vref x code / 4095, RM0090 14.3.5); false if v is not
  /// finite or its volts fall outside 0.2 V .. Vref - 0.2 V by more than half a code.
  bool dac_code(float v, std::uint32_t& code) const {
    const float volts = (v - actuator.offset) / actuator.gain;
    const float half_code = 0.5F * vref_volts / 4095.0F;
    if (!(volts >= kLowestVolts - half_code && volts <= highest_volts() + half_code)) {
      return false;  // NaN too
    }
    // Round half up (no libm call in the image); volts > 0 here.
    code = static_cast<std::uint32_t>(volts * (4095.0F / vref_volts) + 0.5F);
    if (code > analog_registers::kFullScaleCode) code = analog_registers::kFullScaleCode;
    return true;
  }
};

namespace detail {
template <RegisterBus Bus>
void set_bits(Bus& bus, std::uintptr_t address, std::uint32_t bits) {
  bus.write(address, bus.read(address) | bits);
}
// Clocks a pin's port and puts the pin in analog mode (8.3.12: no digital input, no pull).
template <RegisterBus Bus>
void make_analog(Bus& bus, const AnalogPin& pin) {
  using namespace analog_registers;
  set_bits(bus, kRccAhb1enr, pin.rcc_ahb1enr_bit);
  (void)bus.read(kRccAhb1enr);  // the enable takes effect before the port is accessed (ES0182 2.1.13)
  set_bits(bus, pin.gpio_base + kModer, kModeAnalog << (2U * pin.pin));
}
}  // namespace detail

/// PA4 analog, the DAC clocked, channel 1 enabled with its output buffer and without a trigger (a write to DHR12R1
/// reaches DOR1 one APB1 cycle later), at the plan's rest value. The rest is written before the enable and again
/// after it: RM0090 does not say whether DHR moves to DOR while the channel is off, and either way the output is at
/// the rest value within microseconds of the enable. Channel 2's half of DAC_CR is kept.
template <RegisterBus Bus>
void start_dac(Bus& bus, const AnalogPlan& plan) {
  using namespace analog_registers;
  detail::make_analog(bus, AnalogPin{kGpioA, 1U << 0, kDacDacPin});
  detail::set_bits(bus, kRccApb1enr, kApb1enrDacEn);
  (void)bus.read(kRccApb1enr);
  std::uint32_t rest = 0;
  const bool has_rest = plan.dac_code(plan.actuator_rest, rest);  // valid(): always
  if (has_rest) bus.write(kDacDhr12r1, rest);
  bus.write(kDacCr, (bus.read(kDacCr) & ~kDacCrChannel1Mask) | kDacCrEn1);
  if (has_rest) bus.write(kDacDhr12r1, rest);
}

/// The channel's pin analog, ADC1 clocked at PCLK2 / 4, 12-bit right-aligned single conversions of that one channel
/// sampled for 84 cycles, then powered up (ADON) and given its stabilisation time.
template <RegisterBus Bus>
void start_adc(Bus& bus, const AnalogPlan& plan) {
  using namespace analog_registers;
  detail::make_analog(bus, adc_channel_pin(plan.adc_channel));
  detail::set_bits(bus, kRccApb2enr, kApb2enrAdc1En);
  (void)bus.read(kRccApb2enr);
  bus.write(kAdcCcr, (bus.read(kAdcCcr) & ~kCcrAdcpreMask) | kCcrAdcpreDiv4);
  bus.write(kAdcCr1, 0U);  // 12 bits, no scan, no interrupts, no watchdog
  bus.write(kAdcCr2, 0U);  // off, single conversion, EOC after each conversion, right-aligned
  const std::uint32_t channel = plan.adc_channel;
  const std::uintptr_t smpr = channel < 10 ? kAdcSmpr2 : kAdcSmpr1;
  const std::uint32_t shift = 3U * (channel % 10);
  bus.write(smpr, (bus.read(smpr) & ~(7U << shift)) | (kSampleTime84Cycles << shift));
  bus.write(kAdcSqr1, 0U);  // L = 0: one conversion
  bus.write(kAdcSqr3, channel);
  bus.write(kAdcCr2, kCr2Adon);
  for (std::uint32_t i = 0; i < kStabilisationReads; ++i) (void)bus.read(kAdcCr2);
}

/// Sets the DAC to v: kOk; kOutOfRange (v not finite or outside the DAC's range: nothing written).
template <RegisterBus Bus>
[[nodiscard]] Status write_dac(Bus& bus, const AnalogPlan& plan, float v) {
  std::uint32_t code = 0;
  if (!plan.dac_code(v, code)) return Status::kOutOfRange;
  bus.write(analog_registers::kDacDhr12r1, code);
  return Status::kOk;
}

/// One conversion of the plan's channel into y: kOk; kOutOfRange (the code is 0 or 4095: the input may lie beyond
/// the converter's range, y is its clipped value); kTimeout (EOC never came: no value; it ends a run). `emulated`:
/// DR is read without waiting for EOC (QEMU, whose ADC never sets it).
template <RegisterBus Bus>
[[nodiscard]] Status read_adc(Bus& bus, const AnalogPlan& plan, float& y, bool emulated = false) {
  using namespace analog_registers;
  bus.write(kAdcCr2, kCr2Adon | kCr2Swstart);
  if (!emulated && !wait_for_bits(bus, kAdcSr, kSrEoc, kSrEoc, kConversionPolls)) return Status::kTimeout;
  // Reading DR clears EOC. Single software-started conversions, each read before the next starts, cannot overrun
  // (and with EOCS = 0 the ADC does not detect it: RM0090 13.8.1).
  const std::uint32_t code = bus.read(kAdcDr) & kFullScaleCode;
  y = plan.sensor_value(code);
  return code == 0U || code == kFullScaleCode ? Status::kOutOfRange : Status::kOk;
}

/// What sample_then_actuate did: the conversion's status (read_adc's) and the write's (write_dac's).
struct TickStatus {
  Status measured = Status::kOk;
  Status actuated = Status::kOk;
};

/// One sample instant: y(t) is converted first, then v(t) is written. The model A y = B u has no direct feedthrough
/// (b_0 = 0): y(t) must not see v(t). Written first, the DAC's output settles over 3-6 us (t_SETTLING, DS8626) while
/// the ADC samples for 4 us (84 cycles at 21 MHz), and a fast stage, or a sensor wired near the DAC's node, would
/// put part of v(t) into y(t): a b_0 the estimator cannot represent, biasing the other parameters.
template <RegisterBus Bus>
[[nodiscard]] TickStatus sample_then_actuate(Bus& bus, const AnalogPlan& plan, float v, float& y,
                                             bool emulated = false) {
  TickStatus s;
  s.measured = read_adc(bus, plan, y, emulated);
  s.actuated = write_dac(bus, plan, v);
  return s;
}

}  // namespace lashid::hal::stm32f4
