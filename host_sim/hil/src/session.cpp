#include "session.hpp"

#include <fcntl.h>
#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <algorithm>
#include <chrono>
#include <fstream>
#include <optional>
#include <string>
#include <stdexcept>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "lashid/firmware/messages.hpp"
#include "lashid/hal/link_protocol.hpp"
#include "lashid/hil/link_faults.hpp"
#include "plant_peer.hpp"
#include "reports.hpp"
#include "stop_signals.hpp"

namespace lashid::sim::detail {
namespace {

namespace link = hal::link;
using Clock = std::chrono::steady_clock;
using std::chrono::milliseconds;

/// How long the host waits for the answer to a query, the design, the start or a report request before sending it
/// again. A clean exchange takes a few ms; a lost frame costs this much.
constexpr milliseconds kAnswerWait{250};
/// Silence on both UARTs after which the host asks the firmware where it is (its kDone may have been lost).
constexpr milliseconds kSilenceBeforeQuery{500};
/// QEMU silent for this long when the time limit comes: reported as having stopped answering.
constexpr std::chrono::seconds kStalled{2};
/// A frame under way on the plant port lost a byte when, after a silence this long, a new frame starts (the
/// firmware writes a request in one go, and repeats a lost one after 10 ms). QEMU may deliver the bytes one by one,
/// so only the first is looked at: a frame's continuation rarely starts with the sync byte after such a pause.
constexpr milliseconds kPlantFrameGap{5};
/// A QEMU that closed a UART is exiting; one that has not exited this long after is reported as such.
constexpr std::chrono::seconds kExitAfterClose{5};

std::vector<std::uint8_t> command(link::Command c, std::optional<std::uint8_t> argument = std::nullopt) {
  link::PayloadWriter w;
  w.u8(static_cast<std::uint8_t>(c));
  if (argument) w.u8(*argument);
  return frame_bytes(link::MessageType::kCommand, w);
}

class Session {
 public:
  Session(const HilOptions& options, AnyPlant plant, RunRecorder* recorder, const fw::RunDesign& design, pid_t& qemu,
          SessionFds& fds, HilResult& result)
      : options_(options),
        design_(design),
        qemu_(qemu),
        fds_(fds),
        result_(result),
        peer_(std::move(plant), recorder, options.corrupt_every, result),
        streamed_recorder_(options.physical_plant ? recorder : nullptr),
        start_flags_(static_cast<std::uint8_t>(
            link::kStartHoldReports | (streamed_recorder_ != nullptr ? link::kStartStreamSamples : 0U))) {}

  void run() {
    const auto start = Clock::now();
    // At most a year: a larger limit would overflow the clock's nanoseconds (the CLI allows up to 1e6 s).
    const double limit = std::clamp(options_.timeout_seconds, 0.0, 3.15e7);
    const auto deadline =
        start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(limit));
    last_heard_ = start;
    send_link(command(link::Command::kQuery));
    sent_at_ = start;
    for (;;) {
      const auto now = Clock::now();
      if (now > deadline) throw std::runtime_error(timeout_message(now));
      poll_once();
      // Before QEMU's exit is looked at: a Ctrl-C reaches QEMU too, and the user's stop is the reason to report.
      throw_if_stopped();
      if (qemu_ > 0 && exited()) return;
      if (closed_at_ && now - *closed_at_ > kExitAfterClose) {
        throw std::runtime_error(fmt::format("hil: QEMU closed {} but has not exited", closed_what_));
      }
      if (act(Clock::now())) return;
    }
  }

 private:
  enum class Step { kQuery, kDesign, kStart, kRun, kReports, kFinish };

  void send_link(const std::vector<std::uint8_t>& bytes) {
    if (fds_.link < 0 || writes_closed_) return;
    // Whatever the host sends asks for an answer: a report cut short before it must not swallow the answer's start.
    if (link_decoder_.abandon_partial()) ++result_.protocol_errors;
    const auto out = to_link_.pass(bytes.data(), bytes.size());
    if (!write_all(fds_.link, out, "the link (UART0)")) closed_by_peer(nullptr, "the link (UART0)");
  }

  // QEMU closed a UART: `fd` read its end (closed here), or (nullptr) a write found it closed, and what QEMU wrote
  // before is still to be read. When the host started QEMU, QEMU is exiting (the firmware ended the run, or QEMU was
  // killed): the loop reads what is pending and reaps it, which says why (a refused design, a signal). Throwing here
  // would race that exit and hide the reason. A QEMU the user started cannot be reaped: an error unless the host
  // already has every report.
  void closed_by_peer(int* fd, const char* what) {
    if (fd != nullptr) {
      ::close(*fd);
      *fd = -1;
    } else {
      writes_closed_ = true;
    }
    if (qemu_ <= 0) {
      if (reports_complete()) return;
      throw std::runtime_error(fmt::format("hil: QEMU closed {} before the run ended", what));
    }
    if (!closed_at_) closed_at_ = Clock::now();
    closed_what_ = what;
  }

  // Sends `bytes` again if the answer has not come within kAnswerWait (counted as a host retry).
  void resend_if_due(Clock::time_point now, const std::vector<std::uint8_t>& bytes) {
    if (now - sent_at_ < kAnswerWait) return;
    send_link(bytes);
    sent_at_ = now;
    ++sends_;
    ++result_.host_retries;
  }

  void enter(Step step, const std::vector<std::uint8_t>& first, Clock::time_point now) {
    step_ = step;
    send_link(first);
    sent_at_ = now;
    sends_ = first.empty() ? 0 : 1;
  }

  std::vector<std::uint8_t> design_frame() const {
    link::PayloadWriter w;
    design_.encode(w);
    return frame_bytes(link::MessageType::kDesign, w);
  }

  bool firmware_running() const {
    return stage_ != fw::Stage::kIdle || result_.samples > 0 || result_.repeated_requests > 0 || result_.done >= 0;
  }

  bool reports_complete() const {
    bool dis = false, ais = false;
    for (const fw::EstimateRecord& e : result_.estimates) (e.scheme == est::Scheme::kDescending ? dis : ais) = true;
    return result_.done >= 0 && dis && ais && result_.cross_check && result_.cost;
  }

  // The protocol's next step, by what has arrived and how long ago it was asked for. True: the session is over.
  bool act(Clock::time_point now) {
    switch (step_) {
      case Step::kQuery:
        if (stage_seen_) {
          enter(Step::kDesign, design_frame(), now);
        } else if (now - sent_at_ >= milliseconds(100)) {  // the UART may not be enabled yet: not a retry
          send_link(command(link::Command::kQuery));
          sent_at_ = now;
          ++sends_;
        }
        return false;
      case Step::kDesign:
        if (result_.design_status == 0) {
          enter(Step::kStart, command(link::Command::kStart, start_flags_), now);
        } else if (result_.design_status > 0) {
          step_ = Step::kRun;  // refused: the firmware reports and ends the run without starting
        } else {
          resend_if_due(now, design_frame());
        }
        return false;
      case Step::kStart:
        if (firmware_running()) {
          step_ = Step::kRun;
        } else {
          resend_if_due(now, command(link::Command::kStart, start_flags_));
        }
        return false;
      case Step::kRun:
        if (result_.done >= 0 || stage_ == fw::Stage::kDone) {
          enter(Step::kReports, {}, now - kAnswerWait);  // ask at once for what is missing
        } else if (now - last_heard_ >= kSilenceBeforeQuery && now - sent_at_ >= kSilenceBeforeQuery) {
          send_link(command(link::Command::kQuery));  // the firmware's kDone may be lost: where is it?
          sent_at_ = now;
        }
        return false;
      case Step::kReports:
        if (reports_complete()) {
          enter(Step::kFinish, command(link::Command::kFinish), now);
          return qemu_ <= 0;  // attached: QEMU is the user's, the session ends here
        }
        resend_if_due(now, command(link::Command::kReport));
        return false;
      case Step::kFinish:
        if (now - sent_at_ >= kAnswerWait) {  // kFinish lost: QEMU has not exited
          send_link(command(link::Command::kFinish));
          sent_at_ = now;
        }
        return false;
    }
    return false;
  }

  void on_link_bytes(const std::uint8_t* data, std::size_t size) {
    for (const std::uint8_t byte : from_link_.pass(data, size)) {
      const auto r = link_decoder_.push(byte);
      if (r == link::FrameDecoder::Result::kDropped) ++result_.protocol_errors;
      if (r != link::FrameDecoder::Result::kFrame) continue;
      const link::Frame& f = link_decoder_.frame();
      if (f.type == link::MessageType::kSamples) {
        on_samples(f);
        continue;
      }
      collect(f, result_);
      if (f.type != link::MessageType::kStatus) continue;
      auto reader = f.reader();
      const auto stage = static_cast<fw::Stage>(reader.u8());
      const std::uint32_t samples = reader.u32();
      if (!reader.ok()) continue;
      stage_seen_ = true;
      if (stage != stage_ && options_.on_progress) options_.on_progress(stage, samples);
      stage_ = stage;
    }
  }

  // A physical plant's samples as the firmware streamed them (kStartStreamSamples): into the recording, by their
  // index in the run. A block lost on the link leaves a gap, which the recording reports (partial).
  void on_samples(const link::Frame& f) {
    fw::SampleBlock block;
    if (streamed_recorder_ == nullptr || !block.decode(f.reader())) {
      ++result_.protocol_errors;
      return;
    }
    for (std::size_t k = 0; k < block.count; ++k) {
      const std::uint64_t t = std::uint64_t{block.first} + k;
      const bool aside = (block.set_aside & (1U << k)) != 0U;
      // Every one the firmware counted, the interval check's too: the check against its estimates needs them all.
      // Blocks come in order; a repeated one is not counted again.
      if (aside && (result_.set_aside.empty() || result_.set_aside.back() < t)) result_.set_aside.push_back(t);
      // A non-finite sample ends the recording there (the recorder says so in it).
      if (streamed_recorder_->sample(t, block.v[k], block.y[k]) && aside) {
        streamed_recorder_->note(fmt::format("the firmware set aside the row above (sample {} of the run) as a bad "
                                             "sensor value: its y is as measured, the device did not estimate from "
                                             "it",
                                             t));
      }
    }
    // Samples streamed: up to the highest index received (a duplicated block counts once).
    result_.samples = std::max<std::uint32_t>(result_.samples, block.first + block.count);
  }

  void on_plant_bytes(const std::uint8_t* data, std::size_t size) {
    const auto now = Clock::now();
    const bool new_frame = size >= 1 && data[0] == link::kSync0;
    if (new_frame && now - last_plant_byte_ > kPlantFrameGap) peer_.silence();
    last_plant_byte_ = now;
    const auto reply = peer_.receive(from_plant_.pass(data, size));
    if (reply.empty() || fds_.plant < 0 || writes_closed_) return;
    if (!write_all(fds_.plant, to_plant_.pass(reply.data(), reply.size()), "the plant port (UART1)")) {
      closed_by_peer(nullptr, "the plant port (UART1)");
    }
  }

  void poll_once() {
    pollfd fds[3] = {{fds_.link, POLLIN, 0}, {fds_.plant, POLLIN, 0}, {fds_.console, POLLIN, 0}};
    if (::poll(fds, 3, 20) < 0 && errno != EINTR) fail_errno("poll");
    std::uint8_t buffer[4096];
    for (int k = 0; k < 3; ++k) {
      if (fds[k].fd < 0 || (fds[k].revents & (POLLIN | POLLHUP | POLLERR)) == 0) continue;
      int& fd = k == 0 ? fds_.link : k == 1 ? fds_.plant : fds_.console;
      const ssize_t n = ::read(fd, buffer, sizeof(buffer));
      if (n <= 0) {
        if (k < 2) {
          closed_by_peer(&fd, k == 0 ? "the link (UART0)" : "the plant port (UART1)");
        } else {
          ::close(fd);
          fd = -1;
        }
        continue;
      }
      last_heard_ = Clock::now();
      const auto size = static_cast<std::size_t>(n);
      if (k == 0) {
        on_link_bytes(buffer, size);
      } else if (k == 1) {
        on_plant_bytes(buffer, size);
      } else {
        result_.console.append(reinterpret_cast<const char*>(buffer), size);
      }
    }
  }

  // Whether QEMU has exited; then drains what it wrote before and fills the fault counts.
  bool exited() {
    int status = 0;
    if (::waitpid(qemu_, &status, WNOHANG) != qemu_) return false;
    qemu_ = -1;
    result_.qemu_exit = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    std::uint8_t buffer[4096];
    for (int* fd : {&fds_.link, &fds_.console}) {
      if (*fd < 0) continue;
      ::fcntl(*fd, F_SETFL, O_NONBLOCK);
      for (ssize_t n = 0; (n = ::read(*fd, buffer, sizeof(buffer))) > 0;) {
        if (fd == &fds_.link) {
          on_link_bytes(buffer, static_cast<std::size_t>(n));
        } else {
          result_.console.append(reinterpret_cast<const char*>(buffer), static_cast<std::size_t>(n));
        }
      }
    }
    return true;
  }

  // What the host was waiting for when the time ran out. The firmware only answers before and after its run, so a
  // silence means QEMU stopped only while the plant is being played (or when its process is stopped).
  std::string timeout_message(Clock::time_point now) const {
    const double silent = std::chrono::duration<double>(now - last_heard_).count();
    const bool stopped = qemu_ > 0 && process_stopped(qemu_);
    std::string why;
    if (stopped || (step_ == Step::kRun && silent >= std::chrono::duration<double>(kStalled).count())) {
      why = fmt::format("QEMU stopped answering: nothing on its UARTs or console for {:.1f} s{}", silent,
                        stopped ? " (its process is stopped)" : "");
    } else {
      switch (step_) {
        case Step::kQuery: why = fmt::format("the firmware never answered a query on the link (sent {} times)", sends_);
          break;
        case Step::kDesign: why = fmt::format("the firmware has not acknowledged the design (sent {} times)", sends_);
          break;
        case Step::kStart: why = fmt::format("the firmware has not started (start sent {} times)", sends_); break;
        case Step::kRun: why = "the run goes on, too slowly for the limit"; break;
        case Step::kReports: why = fmt::format("reports still missing after asking {} times", sends_); break;
        case Step::kFinish: why = "QEMU has not exited after the host had every report"; break;
      }
      if (options_.fault_rate > 0 && step_ != Step::kFinish) why += ": the link loses too many frames";
    }
    return fmt::format("hil: no end within --timeout {} s ({} samples exchanged): {}", options_.timeout_seconds,
                       result_.samples, why);
  }

  // Linux: whether the process is stopped (SIGSTOP, a debugger): state T or t in /proc/PID/stat.
  static bool process_stopped(pid_t pid) {
    std::ifstream stat(fmt::format("/proc/{}/stat", pid));
    std::string line;
    if (!std::getline(stat, line)) return false;
    const auto close = line.rfind(')');  // the command name may hold spaces and parentheses
    return close != std::string::npos && close + 2 < line.size() &&
           (line[close + 2] == 'T' || line[close + 2] == 't');
  }

 public:
  ~Session() {
    for (const FaultyLine* line : {&to_link_, &from_link_, &to_plant_, &from_plant_}) result_.faults += line->counts();
  }

 private:
  const HilOptions& options_;
  const fw::RunDesign& design_;
  pid_t& qemu_;
  SessionFds& fds_;
  HilResult& result_;
  PlantPeer peer_;
  RunRecorder* streamed_recorder_;  // a physical plant's recording, from the streamed samples (else null)
  std::uint8_t start_flags_;
  link::FrameDecoder link_decoder_;
  // Each direction of each UART has its own draws: the faults of one do not depend on the traffic of another.
  FaultyLine to_link_{options_.fault_rate, options_.fault_seed, 0};
  FaultyLine from_link_{options_.fault_rate, options_.fault_seed, 1};
  FaultyLine to_plant_{options_.fault_rate, options_.fault_seed, 2};
  FaultyLine from_plant_{options_.fault_rate, options_.fault_seed, 3};
  Step step_ = Step::kQuery;
  int sends_ = 1;  // times the current step's request was sent
  bool stage_seen_ = false;
  fw::Stage stage_ = fw::Stage::kIdle;
  Clock::time_point sent_at_{};
  Clock::time_point last_heard_{};
  Clock::time_point last_plant_byte_{};
  std::optional<Clock::time_point> closed_at_;  // when QEMU first closed a UART (the host's own QEMU only)
  const char* closed_what_ = "";
  bool writes_closed_ = false;  // a write found a UART closed: QEMU is going, nothing more is sent
};

}  // namespace

void run_session(const HilOptions& options, AnyPlant plant, RunRecorder* recorder, const fw::RunDesign& design,
                 pid_t& qemu, SessionFds& fds, HilResult& result) {
  Session session(options, std::move(plant), recorder, design, qemu, fds, result);
  session.run();
}

}  // namespace lashid::sim::detail
