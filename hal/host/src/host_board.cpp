#include "lashid/hal/host_board.hpp"

#include <chrono>
#include <cmath>

namespace lashid::hal {

HostBoard::HostBoard(const sim::Scenario& scenario, std::uint64_t seed)
    : plant_(scenario, seed),
      v_min_(static_cast<float>(scenario.config.v_min)),
      v_max_(static_cast<float>(scenario.config.v_max)) {}

Status HostBoard::actuate(float v) {
  if (!std::isfinite(v) || v < v_min_ || v > v_max_) return Status::kOutOfRange;
  // The plant sees the command as the firmware sent it (float), and the firmware sees y as a float sensor value:
  // exactly what crosses the link to `lashid hil`, so host and QEMU runs are comparable.
  y_ = static_cast<float>(plant_.step(static_cast<double>(v)));
  measured_ = false;
  exchanges_.push_back({v, y_});
  return Status::kOk;
}

Status HostBoard::measure(float& y) {
  if (measured_) return Status::kSensorFault;  // measure() without a new actuate(): no new sample exists
  measured_ = true;
  if (!std::isfinite(y_)) return Status::kSensorFault;
  y = y_;
  return Status::kOk;
}

Status HostBoard::wait_for_sample_tick() { return Status::kOk; }  // simulated time: every tick is on time

Status HostBoard::link_write(const std::uint8_t* data, std::size_t size) {
  link_output_.insert(link_output_.end(), data, data + size);
  return Status::kOk;
}

Status HostBoard::link_read(std::uint8_t& byte) {
  if (link_input_.empty()) return Status::kWouldBlock;
  byte = link_input_.front();
  link_input_.pop_front();
  return Status::kOk;
}

void HostBoard::link_input(const std::uint8_t* data, std::size_t size) { link_input_.insert(link_input_.end(), data, data + size); }

std::uint32_t HostBoard::cycles() const {
  // Nanoseconds of the steady clock, wrapping at 2^32 like a cycle counter.
  const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(
      std::chrono::steady_clock::now().time_since_epoch());
  return static_cast<std::uint32_t>(ns.count());
}

}  // namespace lashid::hal
