// Private to the hil layer: decoding the firmware's report frames into a HilResult, for the QEMU session
// (hil.cpp) and the host board run (host_board_run.cpp) alike.
#pragma once

#include "lashid/hal/link_protocol.hpp"
#include "lashid/hil/hil.hpp"

namespace lashid::sim::detail {

/// Stores one report frame of the firmware in `result`; a report that does not decode counts as a protocol error.
void collect(const hal::link::Frame& f, HilResult& result);

}  // namespace lashid::sim::detail
