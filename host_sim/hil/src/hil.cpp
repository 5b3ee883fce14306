#include "lashid/hil/hil.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include <fmt/format.h>

#include "lashid/hal/link_protocol.hpp"
#include "lashid/hil/qemu_args.hpp"
#include "lashid/sim/scenario.hpp"
#include "played_run.hpp"
#include "reports.hpp"

extern char** environ;

namespace lashid::sim {
namespace {

namespace link = hal::link;

[[noreturn]] void fail(const std::string& what) {
  throw std::runtime_error(fmt::format("hil: {}: {}", what, std::strerror(errno)));
}

std::vector<std::uint8_t> frame(link::MessageType type, const link::PayloadWriter& w) {
  std::vector<std::uint8_t> out(link::kMaxFrame);
  out.resize(link::encode_frame(type, 0, w.data(), w.size(), out.data()));
  return out;
}

class UnixListener {
 public:
  explicit UnixListener(const std::filesystem::path& path) : path_(path) {
    fd_ = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd_ < 0) fail("socket");
    sockaddr_un addr{};
    addr.sun_family = AF_UNIX;
    const std::string p = path.string();
    if (p.size() >= sizeof(addr.sun_path)) throw std::runtime_error("hil: socket path too long: " + p);
    std::memcpy(addr.sun_path, p.c_str(), p.size() + 1);
    if (::bind(fd_, reinterpret_cast<const sockaddr*>(&addr), sizeof(addr)) != 0) fail("bind " + p);
    if (::listen(fd_, 1) != 0) fail("listen " + p);
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

void write_all(int fd, const std::vector<std::uint8_t>& bytes) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) fail("write to QEMU");
    done += static_cast<std::size_t>(n);
  }
}

// The host's side of the plant port: answers kActuate(t, v) with kMeasurement(t, y), stepping the plant once per t
// and recording each t once (retries are answered from the cache, not recorded again).
class PlantPeer {
 public:
  PlantPeer(AnyPlant plant, RunRecorder* recorder, int corrupt_every, HilResult& result)
      : plant_(std::move(plant)), recorder_(recorder), corrupt_every_(corrupt_every), result_(result) {}

  // Returns the bytes to send back for the received bytes.
  std::vector<std::uint8_t> receive(const std::uint8_t* data, std::size_t size) {
    std::vector<std::uint8_t> reply;
    for (std::size_t i = 0; i < size; ++i) {
      const auto r = decoder_.push(data[i]);
      if (r == link::FrameDecoder::Result::kDropped) ++result_.protocol_errors;
      if (r != link::FrameDecoder::Result::kFrame) continue;
      const link::Frame& f = decoder_.frame();
      auto reader = f.reader();
      const std::uint32_t t = reader.u32();
      const float v = reader.f32();
      if (f.type != link::MessageType::kActuate || !reader.ok() || !reader.at_end()) {
        ++result_.protocol_errors;
        continue;
      }
      if (t == next_t_) {  // a new sample: step the plant (the command as the firmware sent it, a float)
        last_y_ = static_cast<float>(plant_.step(static_cast<double>(v)));
        if (recorder_ != nullptr) recorder_->sample(t, v, last_y_);
        ++next_t_;
        ++result_.samples;
      } else if (next_t_ > 0 && t == next_t_ - 1) {  // a repeat after a lost/damaged answer: same y
        ++result_.repeated_requests;
      } else {
        ++result_.protocol_errors;
        continue;
      }
      link::PayloadWriter w;
      w.u32(t);
      w.f32(last_y_);
      auto out = frame(link::MessageType::kMeasurement, w);
      if (corrupt_every_ > 0 && ++answers_ % static_cast<std::uint32_t>(corrupt_every_) == 0) {
        out[7] ^= 0x04;  // one bit of y: the firmware must reject it by the checksum
        ++result_.corrupted_by_host;
      }
      reply.insert(reply.end(), out.begin(), out.end());
    }
    return reply;
  }

 private:
  AnyPlant plant_;
  RunRecorder* recorder_;
  int corrupt_every_;
  HilResult& result_;
  link::FrameDecoder decoder_;
  std::uint32_t next_t_ = 0;
  std::uint32_t answers_ = 0;
  float last_y_ = 0;
};

int accept_with_timeout(int listener, int timeout_ms, const char* what) {
  pollfd p{listener, POLLIN, 0};
  if (::poll(&p, 1, timeout_ms) <= 0) {
    throw std::runtime_error(fmt::format("hil: QEMU did not connect to the {} socket", what));
  }
  const int fd = ::accept4(listener, nullptr, nullptr, SOCK_CLOEXEC);
  if (fd < 0) fail(fmt::format("accept ({})", what));
  return fd;
}

int connect_with_timeout(const std::string& path, int timeout_ms) {
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  if (path.size() >= sizeof(addr.sun_path)) throw std::runtime_error("hil: socket path too long: " + path);
  std::memcpy(addr.sun_path, path.c_str(), path.size() + 1);
  for (int waited = 0;; waited += 50) {
    const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd < 0) fail("socket");
    if (::connect(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof(addr)) == 0) return fd;
    ::close(fd);
    if (waited >= timeout_ms) fail("cannot connect to " + path);
    ::usleep(50'000);
  }
}

// Starts QEMU with UART0 (link) and UART1 (plant port) on two Unix sockets the host listens on, and its console
// (semihosting) on a pipe.
void start_qemu(const HilOptions& options, const std::filesystem::path& dir, pid_t& qemu, int& link_fd,
                int& plant_fd, int& out_fd) {
  UnixListener link_listener(dir / "link.sock");
  UnixListener plant_listener(dir / "plant.sock");
  QemuCommand command;
  command.qemu = options.qemu;
  command.machine = options.machine;
  command.serials = {"unix:" + (dir / "link.sock").string(), "unix:" + (dir / "plant.sock").string()};
  // Deterministic virtual time (1 instruction = 1 ns) only on request: QEMU then services the UARTs only between
  // long runs of the vCPU, which makes every exchange slow.
  command.icount = options.icount;
  command.kernel = options.firmware;
  std::vector<std::string> args = qemu_command_line(command);
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  int pipe_fds[2];
  if (::pipe2(pipe_fds, O_CLOEXEC) != 0) fail("pipe");
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, pipe_fds[1], STDOUT_FILENO);
  posix_spawn_file_actions_adddup2(&actions, pipe_fds[1], STDERR_FILENO);
  const int spawn_error = ::posix_spawnp(&qemu, options.qemu.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(pipe_fds[1]);
  out_fd = pipe_fds[0];
  if (spawn_error != 0) {
    errno = spawn_error;
    fail("cannot start " + options.qemu);
  }
  link_fd = accept_with_timeout(link_listener.fd(), 10000, "link (UART0)");
  plant_fd = accept_with_timeout(plant_listener.fd(), 10000, "plant (UART1)");
}

// Decodes the link's bytes into `result`; true when a kStatus frame was among them.
bool feed_link(link::FrameDecoder& decoder, const std::uint8_t* data, std::size_t size, const HilOptions& options,
               HilResult& result) {
  bool status = false;
  for (std::size_t i = 0; i < size; ++i) {
    const auto r = decoder.push(data[i]);
    if (r == link::FrameDecoder::Result::kDropped) ++result.protocol_errors;
    if (r != link::FrameDecoder::Result::kFrame) continue;
    const link::Frame& f = decoder.frame();
    detail::collect(f, result);
    status = status || f.type == link::MessageType::kStatus;
    if (f.type == link::MessageType::kStatus && options.on_progress) {
      auto reader = f.reader();
      const auto stage = static_cast<fw::Stage>(reader.u8());
      const std::uint32_t samples = reader.u32();
      if (reader.ok()) options.on_progress(stage, samples);
    }
  }
  return status;
}

// Waits until the firmware listens: sends kQuery every 100 ms until a kStatus answers. A UART may drop what arrives
// before the firmware has enabled it (QEMU's STM32 USART does, hw/char/stm32f2xx_usart.c: bytes received while
// CR1.UE or RE is clear are discarded; the mps2 UART holds them back instead), so the design must not be sent before.
// Returns early when QEMU's console or the link closes (the run's end is then reported by the caller).
void await_firmware(const HilOptions& options, int link_fd, int out_fd, link::FrameDecoder& decoder,
                    HilResult& result) {
  link::PayloadWriter query;
  query.u8(static_cast<std::uint8_t>(link::Command::kQuery));
  const auto query_frame = frame(link::MessageType::kCommand, query);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(options.timeout_seconds);
  std::uint8_t buffer[4096];
  for (;;) {
    if (std::chrono::steady_clock::now() > deadline) {
      throw std::runtime_error(fmt::format("hil: the firmware did not answer a query on the link within {} s",
                                           options.timeout_seconds));
    }
    write_all(link_fd, query_frame);
    pollfd fds[2] = {{link_fd, POLLIN, 0}, {out_fd, POLLIN, 0}};
    if (::poll(fds, 2, 100) < 0 && errno != EINTR) fail("poll");
    if ((fds[1].revents & (POLLIN | POLLHUP)) != 0) {
      const ssize_t n = ::read(out_fd, buffer, sizeof(buffer));
      if (n <= 0) return;
      result.console.append(reinterpret_cast<const char*>(buffer), static_cast<std::size_t>(n));
    }
    if ((fds[0].revents & (POLLIN | POLLHUP)) != 0) {
      const ssize_t n = ::read(link_fd, buffer, sizeof(buffer));
      if (n <= 0) return;
      if (feed_link(decoder, buffer, static_cast<std::size_t>(n), options, result)) return;
    }
  }
}

// Sends the design and start, plays the plant and collects the reports, until QEMU exits (started by us) or the
// firmware's kDone frame arrives (attached: QEMU belongs to the user).
void run_session(const HilOptions& options, AnyPlant plant, RunRecorder* recorder, const fw::RunDesign& design,
                 pid_t& qemu, int& link_fd, int& plant_fd, int& out_fd, HilResult& result) {
  link::FrameDecoder link_decoder;
  await_firmware(options, link_fd, out_fd, link_decoder, result);
  link::PayloadWriter design_payload;
  design.encode(design_payload);
  write_all(link_fd, frame(link::MessageType::kDesign, design_payload));
  link::PayloadWriter start;
  start.u8(static_cast<std::uint8_t>(link::Command::kStart));
  write_all(link_fd, frame(link::MessageType::kCommand, start));

  PlantPeer peer(std::move(plant), recorder, options.corrupt_every, result);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(options.timeout_seconds);
  std::uint8_t buffer[4096];
  for (;;) {
    if (std::chrono::steady_clock::now() > deadline) {
      throw std::runtime_error(fmt::format("hil: no end after {} s ({} samples exchanged)", options.timeout_seconds,
                                           result.samples));
    }
    pollfd fds[3] = {{link_fd, POLLIN, 0}, {plant_fd, POLLIN, 0}, {out_fd, POLLIN, 0}};
    if (::poll(fds, 3, 100) < 0 && errno != EINTR) fail("poll");
    for (int k = 0; k < 3; ++k) {
      if (fds[k].fd < 0 || (fds[k].revents & (POLLIN | POLLHUP)) == 0) continue;
      const ssize_t n = ::read(fds[k].fd, buffer, sizeof(buffer));
      int& fd = k == 0 ? link_fd : k == 1 ? plant_fd : out_fd;
      if (n <= 0) {
        ::close(fd);
        fd = -1;
        continue;
      }
      const auto size = static_cast<std::size_t>(n);
      if (k == 0) {
        feed_link(link_decoder, buffer, size, options, result);
      } else if (k == 1) {
        const auto reply = peer.receive(buffer, size);
        if (!reply.empty()) write_all(plant_fd, reply);
      } else {
        result.console.append(reinterpret_cast<const char*>(buffer), size);
      }
    }
    if (qemu <= 0) {  // attached
      if (result.done >= 0) return;  // every report precedes kDone on the link
      if (link_fd < 0 || plant_fd < 0) throw std::runtime_error("hil: QEMU closed a UART before the run ended");
      continue;
    }
    int status = 0;
    if (::waitpid(qemu, &status, WNOHANG) != qemu) continue;
    qemu = -1;
    result.qemu_exit = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    // Drain what QEMU wrote before it exited.
    for (int* fd : {&link_fd, &out_fd}) {
      if (*fd < 0) continue;
      ::fcntl(*fd, F_SETFL, O_NONBLOCK);
      for (ssize_t n = 0; (n = ::read(*fd, buffer, sizeof(buffer))) > 0;) {
        if (fd == &link_fd) {
          feed_link(link_decoder, buffer, static_cast<std::size_t>(n), options, result);
        } else {
          result.console.append(reinterpret_cast<const char*>(buffer), static_cast<std::size_t>(n));
        }
      }
    }
    return;
  }
}

}  // namespace

std::vector<std::string> qemu_command_line(const QemuCommand& command) {
  std::vector<std::string> args{command.qemu, "-machine", command.machine};
  args.insert(args.end(), kQemuCommonArgs.begin(), kQemuCommonArgs.end());
  if (command.icount) args.insert(args.end(), kQemuIcountArgs.begin(), kQemuIcountArgs.end());
  for (const std::string& serial : command.serials) args.insert(args.end(), {"-serial", serial});
  args.insert(args.end(), {"-kernel", command.kernel});
  return args;
}

HilResult run_hil(const HilOptions& options) {
  const bool attach = !options.attach_link.empty() || !options.attach_plant.empty();
  if (attach && (options.attach_link.empty() || options.attach_plant.empty())) {
    throw std::runtime_error("hil: attaching needs both sockets (link = UART0, plant = UART1)");
  }
  if (!attach && !std::filesystem::is_regular_file(options.firmware)) {
    throw std::runtime_error("hil: firmware '" + options.firmware + "' not found");
  }
  // The design sent (options.design or the scenario's), the plant played (the scenario's or a plant file's) and
  // the recording, opened before QEMU starts (played_run.hpp).
  const fw::RunDesign design = detail::run_design_of(options);
  AnyPlant plant = detail::played_plant(options, design);
  std::optional<RunRecorder> recorder;
  detail::start_recording(recorder, options, design);
  char dir_template[] = "/tmp/lashid-hil-XXXXXX";
  if (::mkdtemp(dir_template) == nullptr) fail("mkdtemp");
  const std::filesystem::path dir(dir_template);
  HilResult result;
  pid_t qemu = -1;
  int link_fd = -1, plant_fd = -1, out_fd = -1;
  const auto cleanup = [&] {
    for (int fd : {link_fd, plant_fd, out_fd}) {
      if (fd >= 0) ::close(fd);
    }
    if (qemu > 0 && ::waitpid(qemu, nullptr, WNOHANG) == 0) {
      ::kill(qemu, SIGKILL);
      ::waitpid(qemu, nullptr, 0);
    }
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
  };
  try {
    if (attach) {
      link_fd = connect_with_timeout(options.attach_link, 10000);
      plant_fd = connect_with_timeout(options.attach_plant, 10000);
    } else {
      start_qemu(options, dir, qemu, link_fd, plant_fd, out_fd);
    }
    run_session(options, std::move(plant), recorder ? &*recorder : nullptr, design, qemu, link_fd, plant_fd, out_fd,
                result);
  } catch (const std::exception& e) {
    cleanup();
    if (!recorder) throw;
    // A run that stops early keeps what it measured; the run's own error stays the one reported.
    std::string kept;
    try {
      detail::finish_recording(recorder, fmt::format("the host stopped the run: {}", e.what()), result);
      kept = fmt::format("{} samples measured before it are in {} (marked partial)", result.recorded, options.record);
    } catch (const std::exception& r) {
      kept = fmt::format("no recording written: {}", r.what());
    }
    throw std::runtime_error(fmt::format("{}; {}", e.what(), kept));
  }
  cleanup();
  detail::finish_recording(recorder,
                           fmt::format("the firmware's run ended with {}, QEMU exit status {}",
                                       result.done < 0 ? std::string("no report")
                                                       : fmt::format("status '{}'", fw::to_string(
                                                                         static_cast<fw::RunStatus>(result.done))),
                                       result.qemu_exit),
                           result);
  return result;
}

}  // namespace lashid::sim
