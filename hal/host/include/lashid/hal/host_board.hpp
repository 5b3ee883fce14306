// The host board: the firmware's hal::Board on the PC, with the host_sim scenario plant in-process (actuator with
// backlash/switch + linear block + noise) and the byte link as in-memory queues. Same firmware code as on target.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <vector>

#include "lashid/hal/board.hpp"
#include "lashid/sim/scenario.hpp"

namespace lashid::hal {

class HostBoard {
 public:
  struct Exchange {
    float v;
    float y;
  };

  HostBoard(const sim::Scenario& scenario, std::uint64_t seed);

  Status actuate(float v);
  Status measure(float& y);
  Status wait_for_sample_tick();
  Status link_write(const std::uint8_t* data, std::size_t size);
  Status link_read(std::uint8_t& byte);
  std::uint32_t cycles() const;

  /// Bytes the firmware wrote to the link, and bytes to deliver to it.
  const std::vector<std::uint8_t>& link_output() const { return link_output_; }
  void link_input(const std::uint8_t* data, std::size_t size);
  /// Every (v, y) exchanged with the plant, in order.
  const std::vector<Exchange>& exchanges() const { return exchanges_; }

 private:
  sim::ScenarioPlant plant_;
  float v_min_, v_max_;
  float y_ = 0;
  bool measured_ = true;
  std::vector<std::uint8_t> link_output_;
  std::deque<std::uint8_t> link_input_;
  std::vector<Exchange> exchanges_;
};

static_assert(Board<HostBoard>);

}  // namespace lashid::hal
