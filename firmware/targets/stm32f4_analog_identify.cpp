// The identification firmware on an STM32F405 board wired to a physical actuator: the command v leaves on DAC
// channel 1 (PA4), the plant's output y comes back on one ADC1 channel (PA1 by default), once per sample at
// LASHID_ANALOG_SAMPLE_HZ on SysTick; USART1 (PA9/PA10) is the link (design, start/stop/query in, reports out), as
// on every image. The same sequencer as stm32f4_identify.cpp, whose plant is played by `lashid hil` over USART2;
// here nothing is played: `lashid hil --physical-plant` sends the design and reads the reports, and with --record
// the run streams every sample it measured (kSamples) through a transmit queue that USART1's interrupt drains.
//
// The analog plan is the image's (CMake cache, firmware/CMakeLists.txt): LASHID_ANALOG_ADC_CHANNEL, LASHID_ANALOG_VREF
// and the scalings v = V_OFFSET + V_GAIN x (DAC volts), y = Y_OFFSET + Y_GAIN x (ADC volts). A design whose
// [v_min, v_max] reaches beyond what the buffered DAC output reaches (0.2 V to Vref - 0.2 V) in those units is
// refused (kOutsideActuatorRange); an ADC code of 0 or 4095 is a clipped reading, counted as a bad sensor value. The
// DAC holds the actuator at its rest (LASHID_ANALOG_V_REST, else the middle of its range) from power-up to the start
// and again after the run. In QEMU (netduinoplus2: no DAC, an ADC that answers a sawtooth) the run goes through on
// the sawtooth: the CTest hil_stm32f405_physical_plant_* checks the loop.
// Exits with 0 when the run is ok, 10 + RunStatus otherwise, and 9 if the clocks could not be made as planned.
#include <cstdint>

#include "lashid/firmware/sequencer.hpp"
#include "lashid/hal/board.hpp"
#include "lashid/hal/stm32f4.hpp"
#include "lashid/hal/stm32f4/analog.hpp"

// For `lashid hil`: this image's plant is its own (run it with --physical-plant).
LASHID_CORTEX_M_PLANT_TAG("own");

#ifndef LASHID_ANALOG_ADC_CHANNEL
#error "LASHID_ANALOG_ADC_CHANNEL and the other LASHID_ANALOG_* settings come from firmware/CMakeLists.txt"
#endif

namespace {

using namespace lashid;
namespace stm32f4 = hal::stm32f4;

// The actuator rests at LASHID_ANALOG_V_REST before and after a run, else in the middle of its range.
constexpr stm32f4::AnalogPlan analog_plan() {
  stm32f4::AnalogPlan plan{};
  plan.adc_channel = LASHID_ANALOG_ADC_CHANNEL;
  plan.vref_volts = LASHID_ANALOG_VREF;
  plan.actuator = {LASHID_ANALOG_V_OFFSET, LASHID_ANALOG_V_GAIN};
  plan.sensor = {LASHID_ANALOG_Y_OFFSET, LASHID_ANALOG_Y_GAIN};
#ifdef LASHID_ANALOG_V_REST
  plan.actuator_rest = LASHID_ANALOG_V_REST;
  return plan;
#else
  return plan.with_rest_at_middle();
#endif
}
constexpr stm32f4::AnalogPlan kAnalogPlan = analog_plan();
static_assert(kAnalogPlan.valid(),
              "LASHID_ANALOG_*: the ADC channel must be 0-15 but not 4 (PA4 is the DAC's), Vref 2.4-3.6 V, the "
              "offsets finite, the gains finite and non-zero, and V_REST within what the DAC reaches (0.2 V to "
              "Vref - 0.2 V through the actuator's scaling)");
static_assert(LASHID_ANALOG_SAMPLE_HZ >= 1 && LASHID_ANALOG_SAMPLE_HZ <= 10'000,
              "LASHID_ANALOG_SAMPLE_HZ: 1 Hz to 10 kHz (a conversion takes 4.6 us, the estimator's step tens of us)");

// A class of this file's anonymous namespace (internal linkage: the sequencer instantiated on it is inlined).
class Stm32f4AnalogBoard {
 public:
  static constexpr std::uint32_t kCyclesPerSecond = stm32f4::kSystemClockHz;
  /// The link transmits from a queue that USART1's interrupt drains: the sample loop never waits for the wire, so
  /// the run may stream its samples (lashid hil --physical-plant --record), if the link can carry them: a full
  /// kSamples frame is 126 bytes for 14 samples, 9 bytes a sample, and 115200 baud carries 11,520 bytes/s, 1,280
  /// samples/s. Above kMaxStreamedSampleHz (a margin for the status frames) the queue would fill and the samples come
  /// late: the image does not stream then.
  static constexpr std::uint32_t kMaxStreamedSampleHz = 1200;
  static constexpr bool kBuffersLinkWrites = LASHID_ANALOG_SAMPLE_HZ <= kMaxStreamedSampleHz;
  static constexpr std::uint32_t kSamplePeriodCycles = stm32f4::kSystemClockHz / LASHID_ANALOG_SAMPLE_HZ;

  /// `emulated`: no RCC was found (QEMU), whose ADC never signals the end of a conversion (analog.hpp).
  void init(bool emulated) {
    emulated_ = emulated;
    platform_.init(kSamplePeriodCycles);
    stm32f4::start_dac(bus_, kAnalogPlan);  // at the rest value
    stm32f4::start_adc(bus_, kAnalogPlan);
  }
  /// Back to the rest value: after every run, whatever ended it (a refused design, a stop, a fault, the end).
  void rest() { (void)stm32f4::write_dac(bus_, kAnalogPlan, kAnalogPlan.actuator_rest); }

  /// Converts y(t), then writes v(t) (sample_then_actuate: v(t) has no path into y(t)); measure() gives that y(t).
  /// kOk; kOutOfRange outside the DAC's range (not applied; the design check keeps the sequencer inside it).
  hal::Status actuate(float v) {
    const stm32f4::TickStatus s = stm32f4::sample_then_actuate(bus_, kAnalogPlan, v, y_, emulated_);
    measured_ = s.measured;
    return s.actuated;
  }
  /// y(t) as converted at this sample's tick, before v(t) was written. kOk; kOutOfRange for a clipped code (0 or
  /// 4095); kTimeout for a conversion that never ended.
  hal::Status measure(float& y) {
    y = y_;
    return measured_;
  }
  hal::Status wait_for_sample_tick() { return platform_.wait_for_sample_tick(); }
  hal::Status link_write(const std::uint8_t* data, std::size_t size) { return stm32f4::queued_link_write(data, size); }
  hal::Status link_read(std::uint8_t& byte) { return platform_.link_read(byte); }
  std::uint32_t cycles() const { return platform_.cycles(); }

  float actuator_low() const { return kAnalogPlan.actuator_low(); }
  float actuator_high() const { return kAnalogPlan.actuator_high(); }
  std::size_t stack_high_water_bytes() const { return stm32f4::stack_high_water_bytes(); }

 private:
  stm32f4::Stm32f4Platform platform_;
  stm32f4::MmioBus bus_;
  bool emulated_ = false;
  float y_ = 0.0F;                            // this sample's conversion, made in actuate()
  hal::Status measured_ = hal::Status::kTimeout;  // no conversion yet
};

static_assert(hal::Board<Stm32f4AnalogBoard>);
static_assert(hal::LimitsActuatorRange<Stm32f4AnalogBoard>);
static_assert(hal::ReportsStackUse<Stm32f4AnalogBoard>);
static_assert(hal::KnowsCycleRate<Stm32f4AnalogBoard>);
static_assert(hal::BuffersLinkWrites<Stm32f4AnalogBoard> ||
                  LASHID_ANALOG_SAMPLE_HZ > Stm32f4AnalogBoard::kMaxStreamedSampleHz,
              "at 1 kHz, the default, the analog image streams its samples (tests/hil/physical_plant.sh)");

// Static storage: nothing of the sequence lives on the stack, and nothing on a heap (there is none).
Stm32f4AnalogBoard g_board;
fw::IdentificationSequencer<Stm32f4AnalogBoard> g_sequencer(g_board);

}  // namespace

int main() {
  const stm32f4::ClockStart clock = stm32f4::start_clock_tree_and_say();
  if (!stm32f4::runs_as_planned(clock)) return stm32f4::kExitClockTree;
  g_board.init(clock == stm32f4::ClockStart::kFixedByEmulator);
  stm32f4::semihosting::write("lashid: analog identification firmware (DAC1 PA4 out, ADC1 in) waiting on USART1\n");
  const fw::RunStatus status = g_sequencer.run();
  g_board.rest();
  (void)stm32f4::drain_queued_link();  // the last frames leave before the image ends
  return status == fw::RunStatus::kOk ? 0 : 10 + static_cast<int>(status);
}
