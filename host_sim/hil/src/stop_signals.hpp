// Private to the hil layer: SIGINT, SIGTERM and SIGHUP while a run lasts. Their default action would end the tool at
// once, leaving QEMU running, the session's socket folder in the temporary directory and the recording's temporary
// file beside its target. While a StopSignals lives they only set a flag, which the waits of the session poll (at
// least every 20 ms); the run then ends through its normal error path (QEMU killed, files removed, the recording
// kept and marked partial) with HilInterrupted.
#pragma once

namespace lashid::sim::detail {

/// Installs the handlers (without SA_RESTART: a blocking poll() returns EINTR) and clears the flag; the destructor
/// restores the previous handlers. Not reentrant: one run at a time per process.
class StopSignals {
 public:
  StopSignals();
  ~StopSignals();
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;
};

/// Throws HilInterrupted if a stop signal was received.
void throw_if_stopped();

}  // namespace lashid::sim::detail
