#include "qemu_process.hpp"

#include <fcntl.h>
#include <poll.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "lashid/hil/qemu_args.hpp"
#include "stop_signals.hpp"

extern char** environ;

namespace lashid::sim::detail {
namespace {

sockaddr_un socket_address(const std::string& path) {
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  if (path.size() >= sizeof(addr.sun_path)) throw std::runtime_error("hil: socket path too long: " + path);
  std::memcpy(addr.sun_path, path.c_str(), path.size() + 1);
  return addr;
}

class UnixListener {
 public:
  explicit UnixListener(const std::filesystem::path& path) : path_(path) {
    const sockaddr_un addr = socket_address(path.string());
    fd_ = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd_ < 0) fail_errno("socket");
    if (::bind(fd_, reinterpret_cast<const sockaddr*>(&addr), sizeof(addr)) != 0) fail_errno("bind " + path.string());
    if (::listen(fd_, 1) != 0) fail_errno("listen " + path.string());
  }
  ~UnixListener() {
    if (fd_ >= 0) ::close(fd_);
    std::error_code ec;
    std::filesystem::remove(path_, ec);
  }
  UnixListener(const UnixListener&) = delete;
  UnixListener& operator=(const UnixListener&) = delete;
  int fd() const { return fd_; }

 private:
  std::filesystem::path path_;
  int fd_ = -1;
};

// What QEMU wrote before it exited (its console pipe, at end of file), at most a screenful.
std::string exit_words(int console) {
  std::string text;
  char buffer[512];
  for (ssize_t n; text.size() < 2000 && (n = ::read(console, buffer, sizeof buffer)) != 0;) {
    if (n < 0) {
      if (errno == EINTR) continue;
      break;
    }
    text.append(buffer, static_cast<std::size_t>(n));
  }
  while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
  return text.empty() ? std::string("it printed nothing") : text;
}

// Waits for QEMU to connect to `listener`. The console pipe is watched for its end only (events 0: its data stays for
// the session): when QEMU exits first (an unknown machine, an image it cannot load), that is said at once, with
// QEMU's own words, instead of after the whole wait.
int accept_with_timeout(int listener, int console, int timeout_ms, const char* what) {
  pollfd p[2] = {{listener, POLLIN, 0}, {console, 0, 0}};
  int ready = 0;
  // In steps of 20 ms, as the session's loop, so that a stop signal is seen (stop_signals.hpp).
  for (int waited = 0; waited < timeout_ms && ready == 0; waited += 20) {
    ready = ::poll(p, console >= 0 ? 2 : 1, std::min(20, timeout_ms - waited));
    if (ready < 0 && errno == EINTR) ready = 0;
    throw_if_stopped();
  }
  if (ready > 0 && (p[0].revents & POLLIN) == 0 && (p[1].revents & (POLLHUP | POLLERR)) != 0) {
    throw std::runtime_error(
        fmt::format("hil: QEMU exited before it connected to the {} socket: {}", what, exit_words(console)));
  }
  if (ready <= 0) {
    throw std::runtime_error(fmt::format("hil: QEMU did not connect to the {} socket", what));
  }
  const int fd = ::accept4(listener, nullptr, nullptr, SOCK_CLOEXEC);
  if (fd < 0) fail_errno(fmt::format("accept ({})", what));
  return fd;
}

}  // namespace

void fail_errno(const std::string& what) {
  throw std::runtime_error(fmt::format("hil: {}: {}", what, std::strerror(errno)));
}

bool write_all(int fd, const std::vector<std::uint8_t>& bytes, const char* what) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    // send(MSG_NOSIGNAL), not write(): a closed peer is EPIPE here, not a SIGPIPE that kills the tool and leaves
    // its temporary folder and a half-finished recording behind.
    ssize_t n = ::send(fd, bytes.data() + done, bytes.size() - done, MSG_NOSIGNAL);
    // A serial port is not a socket (and cannot raise SIGPIPE): write() there.
    if (n < 0 && errno == ENOTSOCK) n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      if (errno == EPIPE || errno == ECONNRESET) return false;
      fail_errno(fmt::format("write to QEMU's {}", what));
    }
    done += static_cast<std::size_t>(n);
  }
  return true;
}

void start_qemu(const HilOptions& options, const std::filesystem::path& dir, pid_t& qemu, SessionFds& fds) {
  UnixListener link_listener(dir / "link.sock");
  // A physical plant's board has no plant port: its second UART goes nowhere.
  std::optional<UnixListener> plant_listener;
  if (!options.physical_plant) plant_listener.emplace(dir / "plant.sock");
  QemuCommand command;
  command.qemu = options.qemu;
  command.machine = options.machine;
  command.serials = {"unix:" + (dir / "link.sock").string(),
                     options.physical_plant ? std::string("null") : "unix:" + (dir / "plant.sock").string()};
  // Deterministic virtual time (1 instruction = 1 ns) only on request: QEMU then services the UARTs only between
  // long runs of the vCPU, which makes every exchange slow.
  command.icount = options.icount;
  command.kernel = options.firmware;
  std::vector<std::string> args = qemu_command_line(command);
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  int pipe_fds[2];
  if (::pipe2(pipe_fds, O_CLOEXEC) != 0) fail_errno("pipe");
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, pipe_fds[1], STDOUT_FILENO);
  posix_spawn_file_actions_adddup2(&actions, pipe_fds[1], STDERR_FILENO);
  qemu = -1;
  const int spawn_error = ::posix_spawnp(&qemu, options.qemu.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(pipe_fds[1]);
  fds.console = pipe_fds[0];
  if (spawn_error != 0) {
    qemu = -1;
    errno = spawn_error;
    fail_errno("cannot start " + options.qemu);
  }
  fds.link = accept_with_timeout(link_listener.fd(), fds.console, 10000, "link (UART0)");
  if (plant_listener) fds.plant = accept_with_timeout(plant_listener->fd(), fds.console, 10000, "plant (UART1)");
}

namespace {

int open_serial_port(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_CLOEXEC);
  if (fd < 0) fail_errno("cannot open the serial port " + path);
  // Closes the port before the error, keeping the errno that the error reports.
  const auto fail_closing = [fd](const std::string& what) {
    const int e = errno;
    ::close(fd);
    errno = e;
    fail_errno(what);
  };
  termios t{};
  if (::tcgetattr(fd, &t) != 0) fail_closing(path + " is a character device but not a serial port");
  ::cfmakeraw(&t);                    // 8 data bits, no parity, no echo, no line editing or translation
  constexpr tcflag_t kTwoStopBitsAndFlowControl = CSTOPB | CRTSCTS;  // the boards use neither
  constexpr tcflag_t kIgnoreModemLinesAndReceive = CLOCAL | CREAD;
  constexpr tcflag_t kSoftwareFlowControl = IXON | IXOFF | IXANY;
  t.c_cflag &= ~kTwoStopBitsAndFlowControl;
  t.c_cflag |= kIgnoreModemLinesAndReceive;
  t.c_iflag &= ~kSoftwareFlowControl;
  t.c_cc[VMIN] = 1;  // a read after poll() returns what has arrived
  t.c_cc[VTIME] = 0;
  static_assert(kSerialBaud == 115'200, "B115200 below");
  if (::cfsetispeed(&t, B115200) != 0 || ::cfsetospeed(&t, B115200) != 0 || ::tcsetattr(fd, TCSANOW, &t) != 0) {
    fail_closing(fmt::format("cannot set {} to {} baud, 8N1, raw", path, kSerialBaud));
  }
  ::tcflush(fd, TCIOFLUSH);  // what arrived before this run is not part of it
  return fd;
}

}  // namespace

int connect_with_timeout(const std::string& path, int timeout_ms) {
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0) {
    if (S_ISCHR(st.st_mode)) return open_serial_port(path);
    // Something that can never be connected to is said at once, not after the wait for a socket to appear.
    if (!S_ISSOCK(st.st_mode)) {
      const char* what = S_ISDIR(st.st_mode) ? "directory" : S_ISREG(st.st_mode) ? "regular file" : "special file";
      throw std::runtime_error(
          fmt::format("hil: cannot attach to {}: it is a {}, not a Unix socket or a serial port", path, what));
    }
  }
  const sockaddr_un addr = socket_address(path);
  for (int waited = 0;; waited += 50) {
    const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd < 0) fail_errno("socket");
    if (::connect(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof(addr)) == 0) return fd;
    const int why = errno;
    ::close(fd);
    if (waited >= timeout_ms) {
      throw std::runtime_error(fmt::format("hil: cannot connect to {}: {} (waited {:.2g} s for it)", path,
                                           std::strerror(why), waited / 1000.0));
    }
    ::usleep(50'000);
    throw_if_stopped();
  }
}

}  // namespace lashid::sim::detail
