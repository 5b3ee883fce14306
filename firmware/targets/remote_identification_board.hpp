// The hal::Board of the identification image on any Cortex-M board of the project: the board's platform half (the link
// UART, SysTick, the sample tick) plus the actuator/sensor as hal::RemotePlantPort over a second UART, which `lashid
// hil` plays (the actuator with backlash and the plant). One exchange per sample. The per-board images
// (mps2_identify.cpp, stm32f4_identify.cpp) only name their platform, their plant UART and their clock.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>

#include "lashid/hal/board.hpp"
#include "lashid/hal/cortex_m.hpp"
#include "lashid/hal/remote_plant_port.hpp"

namespace lashid::fw::targets {

/// A UART of the board as the byte channel of the remote plant port.
template <typename Uart>
class UartChannel {
 public:
  template <typename Port>
  explicit constexpr UartChannel(const Port& port) : uart_(port) {}
  void init() const {
    uart_.init();
    hal::cortex_m::enable_irq(LASHID_PLANT_RX_IRQ);
  }
  /// Nothing to read yet: asleep until an interrupt (the answer's first byte, SysTick's next zero event or the
  /// link), so that the core does not poll.
  void idle() {
    hal::cortex_m::sleep_until_interrupt_unless([this] {
      uart_.arm_rx_wake();
      return uart_.rx_pending();
    });
  }
  hal::Status write(const std::uint8_t* data, std::size_t size) { return uart_.write(data, size); }
  hal::Status read(std::uint8_t& byte) { return uart_.read(byte); }
  std::uint32_t cycles() const { return hal::cortex_m::SysTickClock::cycles(); }

 private:
  Uart uart_;
};

/// Platform: init(period), link_write/link_read, wait_for_sample_tick, cycles. Uart: the plant port's UART type,
/// constructed from `plant_port`. SystemClockHz: SysTick's processor clock.
template <typename Platform, typename Uart, std::uint32_t SystemClockHz>
class RemoteIdentificationBoard {
 public:
  /// A damaged answer is requested again at once; a lost one after 10 ms, then 20, 40, ... ms (the port doubles
  /// the wait): 10 repetitions wait 20 s in all before the sample is given up as a sensor fault. A normal exchange
  /// with `lashid hil` takes about 1 ms; a host that stalls (a loaded machine) costs a few repeated requests,
  /// answered from its cache, not a failed run.
  static constexpr std::uint32_t kExchangeTimeoutCycles = SystemClockHz / 100;
  static constexpr int kExchangeRetries = 10;
  /// cycles() counts processor cycles (hal::KnowsCycleRate: bounds the hold of the reports after a run).
  static constexpr std::uint32_t kCyclesPerSecond = SystemClockHz;
  /// Sample period: 1 ms. In QEMU the exchange with the host takes longer in virtual time, so ticks are late
  /// (kTimeout, counted, harmless): the sample rate is set by the host-in-the-loop, not by the clock.
  static constexpr std::uint32_t kSamplePeriodCycles = SystemClockHz / 1000;

  template <typename Port>
  explicit constexpr RemoteIdentificationBoard(const Port& plant_port) : plant_channel_(plant_port) {}

  void init() {
    platform_.init(kSamplePeriodCycles);
    plant_channel_.init();
  }

  /// The sequencer commands only the accepted design's levels; a non-finite command never reaches the actuator.
  hal::Status actuate(float v) {
    if (!std::isfinite(v)) return hal::Status::kOutOfRange;
    return port_.actuate(v);
  }
  /// kOutOfRange: the sensor sent a NaN or infinite value (counted by the sequencer, not estimated from).
  hal::Status measure(float& y) { return port_.measure(y); }
  hal::Status wait_for_sample_tick() { return platform_.wait_for_sample_tick(); }
  hal::Status link_write(const std::uint8_t* data, std::size_t size) { return platform_.link_write(data, size); }
  hal::Status link_read(std::uint8_t& byte) { return platform_.link_read(byte); }
  std::uint32_t cycles() const { return platform_.cycles(); }

  // Optional extensions the sequencer reports when present.
  std::size_t stack_high_water_bytes() const { return hal::cortex_m::stack_high_water_bytes(); }
  std::uint32_t exchange_errors() const { return port_.errors(); }
  std::uint32_t exchange_retries() const { return port_.retries(); }

 private:
  Platform platform_{};
  UartChannel<Uart> plant_channel_;
  hal::RemotePlantPort<UartChannel<Uart>> port_{plant_channel_, kExchangeTimeoutCycles, kExchangeRetries};
};

}  // namespace lashid::fw::targets
