// Private to the hil layer: QEMU as a child process with its UARTs on Unix sockets, and the byte I/O on them. The
// only POSIX process and socket code of the project.
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "lashid/hil/hil.hpp"

namespace lashid::sim::detail {

/// The descriptors of a session: UART0 (link), UART1 (plant port), QEMU's console (semihosting, a pipe). -1: closed.
struct SessionFds {
  int link = -1;
  int plant = -1;
  int console = -1;
};

/// Throws std::runtime_error "hil: WHAT: strerror(errno)".
[[noreturn]] void fail_errno(const std::string& what);

/// Writes every byte to a socket or a serial port. False: the peer has closed it (QEMU exited or was killed; never a
/// SIGPIPE). Any other failure throws, naming `what`.
[[nodiscard]] bool write_all(int fd, const std::vector<std::uint8_t>& bytes, const char* what);

/// Starts QEMU with options.firmware, UART0 and UART1 on two sockets in `dir` that the host listens on, and its
/// console on a pipe. Sets `qemu` to its pid as soon as it runs (also when connecting then fails, for the caller
/// to kill it) and fills the descriptors.
void start_qemu(const HilOptions& options, const std::filesystem::path& dir, pid_t& qemu, SessionFds& fds);

/// Attaches to `path`: a Unix socket of a QEMU started by the user (connecting, retrying for up to timeout_ms), or a
/// serial port (a character device: a board's UART through a USB adapter, or a pseudo-terminal such as QEMU's
/// `-serial pty`), opened raw at the firmware's 115200 baud, 8N1, no flow control, its pending input dropped.
int connect_with_timeout(const std::string& path, int timeout_ms);

/// The line settings the firmware's UARTs use (kDefaultBaud of the boards).
inline constexpr unsigned kSerialBaud = 115'200;

}  // namespace lashid::sim::detail
