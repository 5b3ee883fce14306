// The host board: the firmware's hal::Board on the PC, with a plant model stepped in-process (any hal::PlantModel:
// host_sim's actuator + linear block + noise in the tools, a fake in unit tests) and the byte link as in-memory
// queues. Same firmware code as on target.
#pragma once

#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <utility>
#include <vector>

#include "lashid/hal/board.hpp"
#include "lashid/hal/plant_model.hpp"

namespace lashid::hal {

template <PlantModel Plant>
class HostBoard {
 public:
  /// The link is memory: writes never wait (hal::BuffersLinkWrites), so a run may stream its samples.
  static constexpr bool kBuffersLinkWrites = true;

  struct Exchange {
    float v;
    float y;
  };

  /// Commands outside [v_min, v_max] are refused with kOutOfRange, as a real actuator driver would.
  HostBoard(Plant plant, float v_min, float v_max) : plant_(std::move(plant)), v_min_(v_min), v_max_(v_max) {}

  /// kOutOfRange: v is not finite or outside [v_min, v_max]; the plant is not stepped.
  Status actuate(float v) {
    if (!std::isfinite(v) || v < v_min_ || v > v_max_) return Status::kOutOfRange;
    // The plant sees the command as the firmware sent it (float), and the firmware sees y as a float sensor value:
    // exactly what crosses the link to `lashid hil`, so host and QEMU runs are comparable.
    y_ = static_cast<float>(plant_.step(static_cast<double>(v)));
    measured_ = false;
    exchanges_.push_back({v, y_});
    return Status::kOk;
  }

  /// kSensorFault: no actuate() since the last measure() (no new sample exists). kOutOfRange: the plant's y is not
  /// finite (y unchanged; the firmware counts the sample as bad and goes on, as with a remote plant's NaN).
  Status measure(float& y) {
    if (measured_) return Status::kSensorFault;
    measured_ = true;
    if (!std::isfinite(y_)) return Status::kOutOfRange;
    y = y_;
    return Status::kOk;
  }

  Status wait_for_sample_tick() { return Status::kOk; }  // simulated time: every tick is on time

  Status link_write(const std::uint8_t* data, std::size_t size) {
    link_output_.insert(link_output_.end(), data, data + size);
    return Status::kOk;
  }

  /// kWouldBlock when no byte is queued.
  Status link_read(std::uint8_t& byte) {
    if (link_input_.empty()) return Status::kWouldBlock;
    byte = link_input_.front();
    link_input_.pop_front();
    return Status::kOk;
  }

  /// cycles() counts nanoseconds (hal::KnowsCycleRate).
  static constexpr std::uint32_t kCyclesPerSecond = 1'000'000'000;

  /// Nanoseconds of the steady clock, wrapping at 2^32 like a cycle counter.
  std::uint32_t cycles() const {
    const auto ns =
        std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch());
    return static_cast<std::uint32_t>(ns.count());
  }

  /// Bytes the firmware wrote to the link, and bytes to deliver to it.
  const std::vector<std::uint8_t>& link_output() const { return link_output_; }
  void link_input(const std::uint8_t* data, std::size_t size) { link_input_.insert(link_input_.end(), data, data + size); }
  /// Every (v, y) exchanged with the plant, in order.
  const std::vector<Exchange>& exchanges() const { return exchanges_; }

 private:
  Plant plant_;
  float v_min_, v_max_;
  float y_ = 0;
  bool measured_ = true;
  std::vector<std::uint8_t> link_output_;
  std::deque<std::uint8_t> link_input_;
  std::vector<Exchange> exchanges_;
};

namespace detail {
struct ConstantPlant {
  double step(double) { return 0.0; }
};
}  // namespace detail
static_assert(Board<HostBoard<detail::ConstantPlant>>);

}  // namespace lashid::hal
