// Private to the hil layer: the host's frames to the firmware, and the firmware's report frames decoded into a
// HilResult, for the QEMU session (session.cpp, plant_peer.hpp) and the host board run (host_board_run.cpp) alike.
#pragma once

#include <cstdint>
#include <vector>

#include "lashid/hal/link_protocol.hpp"
#include "lashid/hil/hil.hpp"

namespace lashid::sim::detail {

/// One frame of `type` with the payload written in `w`, as the bytes to send.
inline std::vector<std::uint8_t> frame_bytes(hal::link::MessageType type, const hal::link::PayloadWriter& w) {
  std::vector<std::uint8_t> out(hal::link::kMaxFrame);
  out.resize(hal::link::encode_frame(type, 0, w.data(), w.size(), out.data()));
  return out;
}

/// Stores one report frame of the firmware in `result`; a report that does not decode counts as a protocol error.
void collect(const hal::link::Frame& f, HilResult& result);

}  // namespace lashid::sim::detail
