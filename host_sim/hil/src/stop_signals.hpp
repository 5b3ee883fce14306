// Private to the hil layer: the stop signals of io (lashid/io/stop_signals.hpp) while a run lasts; the waits of the
// session poll them (at least every 20 ms), and the run then ends through its normal error path (QEMU killed, files
// removed, the recording kept and marked partial) with HilInterrupted.
#pragma once

#include "lashid/io/stop_signals.hpp"

namespace lashid::sim::detail {

using lashid::sim::StopSignals;

/// Throws HilInterrupted if a stop signal was received.
void throw_if_stopped();

}  // namespace lashid::sim::detail
