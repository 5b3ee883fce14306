// Private to the hil layer: one session with the firmware over its two UARTs, from the first query to the last
// report. Every step that crosses the link is checked and repeated until its answer arrives, so that a link that
// drops, garbles or duplicates bytes (a real one, or ByteFaults with --fault-rate) costs time, never a wrong result:
//   query until a kStatus answers -> design until its kDesignStatus -> start (holding the reports) until the
//   firmware is seen running -> the plant played on UART1, the reports collected from UART0 -> on kDone, or a kStatus
//   saying the run is over: kReport until every report has arrived -> kFinish until QEMU exits.
#pragma once

#include <sys/types.h>

#include <optional>

#include "lashid/firmware/run_design.hpp"
#include "lashid/hil/any_plant.hpp"
#include "lashid/hil/hil.hpp"
#include "lashid/hil/run_recording.hpp"
#include "qemu_process.hpp"

namespace lashid::sim::detail {

/// Runs the session to its end: QEMU's exit when `qemu` > 0 (started by the host; set to -1 once it exited, its
/// status in result.qemu_exit), or every report received when attached (qemu <= 0). Throws std::runtime_error naming
/// what stopped it: the time limit (and for how long QEMU had been silent), a UART closed before the end, a socket
/// error. Closed descriptors are set to -1; the caller closes the others.
void run_session(const HilOptions& options, AnyPlant plant, RunRecorder* recorder, const fw::RunDesign& design,
                 pid_t& qemu, SessionFds& fds, HilResult& result);

}  // namespace lashid::sim::detail
