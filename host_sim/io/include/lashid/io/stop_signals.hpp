// SIGINT, SIGTERM and SIGHUP while a long command runs (hil's session, simulate's stream). Their default action would
// end the tool at once, leaving what it was writing beside its target (a recording's temporary file, QEMU and the
// session's socket folder for hil). While a StopSignals lives they only set a flag, which the command polls; it then
// ends through its normal error path (temporary files removed, targets as they were) with an Interrupted exception,
// and the CLI exits with 128 + the signal, as a shell reports a command a signal ended.
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>

namespace lashid::sim {

/// A command stopped by SIGINT, SIGTERM or SIGHUP. signal(): the signal's number.
class Interrupted : public std::runtime_error {
 public:
  Interrupted(const std::string& what, int signal) : std::runtime_error(what), signal_(signal) {}
  int signal() const { return signal_; }

 private:
  int signal_;
};

/// Installs the handlers (without SA_RESTART: a blocking poll() returns EINTR) and clears the flag; the destructor
/// restores the previous handlers. Not reentrant: one command at a time per process.
class StopSignals {
 public:
  StopSignals();
  ~StopSignals();
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;
};

/// The stop signal received since the last StopSignals was made (0: none). A read of a sig_atomic_t: cheap enough
/// to poll once per sample.
int pending_stop_signal();

/// "<command>: stopped by SIGINT (signal 2)" for a pending signal.
std::string stopped_message(std::string_view command, int signal);

/// Throws Interrupted (stopped_message(command, ...)) if a stop signal was received.
void throw_if_stopped(std::string_view command);

}  // namespace lashid::sim
