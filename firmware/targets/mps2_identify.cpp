// The identification firmware on QEMU's mps2 machines: UART0 is the link (start/stop/query commands in, reports out),
// UART1 is the actuator/sensor port (one kActuate/kMeasurement exchange per sample with `lashid hil`, which plays
// the actuator with backlash and the plant), SysTick is the clock. One image for every design within its capacity
// (n <= 4, m <= 10): it waits for the design (kDesign, answered with its DesignStatus) and a start command, runs the
// sequence, reports, and exits QEMU with 0 when the run is ok (10 + RunStatus otherwise).
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "lashid/firmware/sequencer.hpp"
#include "lashid/hal/board.hpp"
#include "lashid/hal/mps2.hpp"
#include "lashid/hal/remote_plant_port.hpp"

namespace {

using namespace lashid;
namespace mps2 = hal::mps2;

inline constexpr std::uintptr_t kUart1Base = 0x4000'5000;  // CMSDK APB UART1 (QEMU `info mtree`)

/// UART1 as the byte channel of the remote plant port.
class Uart1Channel {
 public:
  void init() const { uart_.init(); }
  hal::Status write(const std::uint8_t* data, std::size_t size) { return uart_.write(data, size); }
  hal::Status read(std::uint8_t& byte) { return uart_.read(byte); }
  std::uint32_t cycles() const { return mps2::SysTickClock::cycles(); }

 private:
  mps2::Mps2Uart uart_{kUart1Base};
};

/// The hal::Board of the identification firmware on mps2.
class Mps2IdentificationBoard {
 public:
  /// A lost answer is requested again after 1 s of virtual time (25 M cycles); a damaged one at once.
  static constexpr std::uint32_t kExchangeTimeoutCycles = mps2::kSystemClockHz;
  static constexpr int kExchangeRetries = 3;
  /// Sample period: 1 ms. In QEMU the exchange with the host takes longer in virtual time, so ticks are late
  /// (kTimeout, counted, harmless): the sample rate is set by the host-in-the-loop, not by the clock.
  static constexpr std::uint32_t kSamplePeriodCycles = mps2::kSystemClockHz / 1000;

  void init() {
    platform_.init(kSamplePeriodCycles);
    plant_channel_.init();
  }

  /// The sequencer commands only the accepted design's levels; a non-finite command never reaches the actuator.
  hal::Status actuate(float v) {
    if (!std::isfinite(v)) return hal::Status::kOutOfRange;
    return port_.actuate(v);
  }
  hal::Status measure(float& y) { return port_.measure(y); }
  hal::Status wait_for_sample_tick() { return platform_.wait_for_sample_tick(); }
  hal::Status link_write(const std::uint8_t* data, std::size_t size) { return platform_.link_write(data, size); }
  hal::Status link_read(std::uint8_t& byte) { return platform_.link_read(byte); }
  std::uint32_t cycles() const { return platform_.cycles(); }

  // Optional extensions the sequencer reports when present.
  std::size_t stack_high_water_bytes() const { return mps2::stack_high_water_bytes(); }
  std::uint32_t exchange_errors() const { return port_.errors(); }
  std::uint32_t exchange_retries() const { return port_.retries(); }

 private:
  mps2::Mps2Platform platform_{};
  Uart1Channel plant_channel_{};
  hal::RemotePlantPort<Uart1Channel> port_{plant_channel_, kExchangeTimeoutCycles, kExchangeRetries};
};

static_assert(hal::Board<Mps2IdentificationBoard>);
static_assert(hal::ReportsStackUse<Mps2IdentificationBoard>);
static_assert(hal::ReportsExchangeErrors<Mps2IdentificationBoard>);

// Static storage: nothing of the sequence lives on the stack, and nothing on a heap (there is none).
Mps2IdentificationBoard g_board;
fw::IdentificationSequencer<Mps2IdentificationBoard> g_sequencer(g_board);

}  // namespace

int main() {
  g_board.init();
  mps2::semihosting::write("lashid: identification firmware waiting for a design and start on UART0\n");
  const fw::RunStatus status = g_sequencer.run();
  return status == fw::RunStatus::kOk ? 0 : 10 + static_cast<int>(status);
}
