// The identification sequence as a state machine, one sample per step(), behind any hal::Board, for any design
// within the image's capacity (run_design.hpp: n <= 4, m <= 10), received at run time:
//   kDesign -> check_design (answered with kDesignStatus; a refused design ends the run, nothing is actuated) ->
//   kStart -> [interval check, Section 3.4 step 1 (backlash)] -> DIS step experiment (3.4) -> DP pulse experiment
//   (3.1) with the recursive estimator updated every sample and solved once per pulse period -> DIS estimate -> AIS
//   step experiment (4.1) -> AP pulse experiment (4.2) -> AIS estimate -> validation phase (ValidationExcitation)
//   -> cross-check of the two linear estimates (Remark 3b) -> reports over the link (estimates, cross-check, cost)
//   -> done [-> holding the reports: sent again on kReport, until kFinish or kReportHoldSeconds].
// Each change to a measuring stage is announced with a kStatus frame (progress for the host); the end is the
// reports, then kDone with the run's status. Commands over the link
// (hal/link_protocol.hpp, framed_link.hpp): design, start, stop, query, report, finish. A sensor value that is NaN, infinite or
// outside the design's sensor range is counted (CostRecord::bad_sensor_values) and never estimated from. On a board
// whose link writes do not wait (hal::BuffersLinkWrites), a start with kStartStreamSamples also sends every sample
// as measured (kSamples, SampleBlock), for the host's recording of a plant it does not play.
// Heap-free, no exceptions, float32.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "lashid/estimator/excitation.hpp"
#include "lashid/estimator/identifier.hpp"
#include "lashid/firmware/framed_link.hpp"
#include "lashid/firmware/messages.hpp"
#include "lashid/firmware/run_design.hpp"
#include "lashid/firmware/run_report.hpp"
#include "lashid/firmware/sample_stream.hpp"
#include "lashid/firmware/validation_excitation.hpp"
#include "lashid/hal/board.hpp"
#include "lashid/hal/link_protocol.hpp"

namespace lashid::fw {

template <hal::Board B>
class IdentificationSequencer {
 public:
  static constexpr int N = kMaxOrder;
  static constexpr int M = kMaxPoints;
  /// With kStartHoldReports: how long the reports are held after a run for a host that lost one (each kReport
  /// starts the wait again). Only on boards that know their cycle rate (hal::KnowsCycleRate); others do not hold.
  static constexpr std::uint32_t kReportHoldSeconds = 2;
  /// Bytes or link errors handled per poll of the link at most (framed_link.hpp).
  static constexpr int kPollBudget = FramedLink<B>::kPollBudget;
  using Identifier = est::SchemeIdentifier<float, N, M>;
  using Estimate = typename Identifier::Estimate;
  using Design = est::ExperimentDesign<float, M>;

  /// Waits in Stage::kIdle for a design (kDesign) and a start command on the link.
  explicit IdentificationSequencer(B& board) : board_(board), link_(board) {}
  /// Runs `design` without waiting for the link (the host tests, a fixed-design image). A design that breaks a
  /// rule ends the run at once with RunStatus::kDesignRejected, as if it had come over the link.
  IdentificationSequencer(B& board, const RunDesign& design) : board_(board), link_(board), started_(true) {
    accept(design);
  }

  /// Runs to the end (or until stopped). Returns the overall status, also sent in the kDone frame.
  RunStatus run() {
    while (step()) {
    }
    return result_;
  }

  /// Does one unit of work (one sample in the experiments). False once the sequence is over.
  bool step() {
    poll_link();
    switch (stage_) {
      case Stage::kIdle:
        if (started_) {
          if (!design_ok_) {
            finish(RunStatus::kDesignRejected);  // a start without an accepted design: nothing runs
          } else {
            enter(design_.checks_interval() ? Stage::kIntervalCheck : Stage::kStepD);
          }
        }
        return true;
      case Stage::kIntervalCheck: return interval_check_sample();
      case Stage::kStepD:
      case Stage::kStepA: return step_sample();
      case Stage::kPulseD:
      case Stage::kPulseA: return pulse_sample();
      case Stage::kValidation: return validation_sample();
      case Stage::kReport:
        report();
        return holding();
      case Stage::kDone: return holding();
    }
    return false;
  }

  Stage stage() const { return stage_; }
  RunStatus result() const { return result_; }
  DesignStatus design_status() const { return design_status_; }
  const RunDesign& design() const { return design_; }
  const Estimate& latest() const { return latest_; }
  /// The schemes' final estimates as reported (status kNotExcited for a scheme that did not run).
  const EstimateRecord& dis() const { return dis_; }
  const EstimateRecord& ais() const { return ais_; }
  const CrossCheckRecord& cross_check() const { return cross_; }
  const CostRecord& cost() const { return cost_; }

 private:
  /// Checks and keeps a design; a refused one ends the run (reported, nothing actuated).
  void accept(const RunDesign& d) {
    design_status_ = check_design(d);
    if constexpr (hal::LimitsActuatorRange<B>) {
      // Every level lies in [v_min, v_max] (check_design), and so does the validation phase.
      if (design_status_ == DesignStatus::kOk &&
          !(d.v_min >= board_.actuator_low() && d.v_max <= board_.actuator_high())) {
        design_status_ = DesignStatus::kOutsideActuatorRange;
      }
    }
    design_ok_ = design_status_ == DesignStatus::kOk;
    if (design_ok_) {
      design_ = d;
    } else {
      finish(RunStatus::kDesignRejected);
    }
  }

  void enter(Stage next) {
    flush_samples();  // a block never spans two stages: each frame's samples are sent before the status
    stage_ = next;
    t_ = 0;
    phase_ = 0;
    if (next == Stage::kStepD || next == Stage::kStepA) {
      const Design d =
          scheme_design(design_, next == Stage::kStepD ? est::Scheme::kDescending : est::Scheme::kAscending);
      (void)identifier_.configure(d, design_.n);  // valid: check_design() accepted the run's design
      generator_ = est::ExcitationGenerator<float, N, M>(d, design_.n);
    } else if (next == Stage::kValidation) {
      validation_.restart(design_);
    }
    send_status();
  }

  void finish(RunStatus status) {
    flush_samples();
    result_ = status;
    stage_ = Stage::kReport;
  }

  auto samples_sender() {
    return [this](const hal::link::PayloadWriter& w) { send(hal::link::MessageType::kSamples, w); };
  }
  void flush_samples() { samples_.flush(samples_sender()); }

  /// One plant exchange at the next sample instant. False (and the run is finished) on a board failure.
  /// A bad sensor value (kOutOfRange from the board, or a value that is not finite or outside the design's sensor
  /// range) is counted and replaced by NaN: the estimator leaves out every row that holds it (rejected_samples).
  bool exchange(float v, float& y) {
    // A late tick (kTimeout) is not an error: the sample is taken late. Boards count overruns themselves.
    (void)board_.wait_for_sample_tick();
    if (board_.actuate(v) != hal::Status::kOk) {
      finish(RunStatus::kActuatorFault);
      return false;
    }
    const hal::Status s = board_.measure(y);
    if (s == hal::Status::kStopped) {
      finish(RunStatus::kStopped);
      return false;
    }
    if (s != hal::Status::kOk && s != hal::Status::kOutOfRange) {
      finish(RunStatus::kSensorFault);
      return false;
    }
    const bool bad = s == hal::Status::kOutOfRange || !design_.sensor_value_ok(y);
    samples_.add(cost_.samples, v, y, bad, samples_sender());  // as measured (with kStartStreamSamples)
    if (bad) {
      ++cost_.bad_sensor_values;
      y = std::numeric_limits<float>::quiet_NaN();
    }
    ++cost_.samples;
    return true;
  }

  bool interval_check_sample() {
    const auto half_period = static_cast<std::uint32_t>(2 * design_.period());
    const bool high = (t_ / half_period) % 2 == 0;
    float y = 0;
    if (!exchange(high ? design_.v_max : design_.v_min, y)) return true;
    if (t_ >= 2 * half_period && t_ % half_period >= half_period / 2) {
      est::StepMean<float>& half = high ? high_ : low_;
      (void)half.add(static_cast<std::int64_t>(half.count()) + 1, y);
    }
    if (++t_ < design_.interval_check_samples()) return true;
    // Without two usable readings at each end nothing can be judged: the sensor's fault, not the interval's.
    if (high_.count() < 2 || low_.count() < 2) {
      finish(RunStatus::kSensorFault);
      return true;
    }
    // Fig. 5 / Remark 1b: if the interval is too narrow the output stops following v after a cycle, so the mean
    // output at v_M and at v_m coincide (up to noise). Require a difference beyond 6 standard errors.
    const float spread = std::sqrt(high_.variance() / static_cast<float>(high_.count()) +
                                   low_.variance() / static_cast<float>(low_.count()));
    if (!(std::fabs(high_.mean() - low_.mean()) > 6.0f * spread)) {
      finish(RunStatus::kIntervalTooNarrow);
    } else {
      enter(Stage::kStepD);
    }
    return true;
  }

  bool step_sample() {
    const float v = generator_.step_input(t_);
    float y = 0;
    if (!exchange(v, y)) return true;
    // On the design by construction; a non-finite y is left out of the mean, and counted.
    if (identifier_.add_step_sample(v, y) != est::Status::kOk) ++cost_.rejected_samples;
    if (++t_ > design_.step_length) enter(stage_ == Stage::kStepD ? Stage::kPulseD : Stage::kPulseA);
    return true;
  }

  bool pulse_sample() {
    const float v = generator_.pulse_input_at_phase(phase_);
    float y = 0;
    if (!exchange(v, y)) return true;
    const std::uint32_t start = board_.cycles();
    const est::Status update = identifier_.add_pulse_sample(v, y);
    cost_.update_cycles += board_.cycles() - start;
    ++cost_.updates;
    if (update != est::Status::kOk) ++cost_.rejected_samples;  // a row left out of the least squares
    ++t_;
    if (++phase_ == generator_.period()) phase_ = 0;
    const bool dis = stage_ == Stage::kPulseD;
    const std::uint32_t length = dis ? design_.pulse_length_d : design_.pulse_length_a;
    if (phase_ == 0 || t_ == length) {  // an up-to-date estimate at least once per pulse period
      const std::uint32_t solve_start = board_.cycles();
      identifier_.estimate_into(latest_, /*with_std_errors=*/false);
      cost_.solve_cycles += board_.cycles() - solve_start;
      ++cost_.solves;
    }
    if (t_ == length) {
      // The final estimate, with standard errors (cross-check, report), kept as its record: a third of the RAM.
      identifier_.estimate_into(latest_);
      (dis ? dis_ : ais_) = to_record(latest_, dis ? est::Scheme::kDescending : est::Scheme::kAscending, design_);
      if (dis) {
        enter(Stage::kStepA);
      } else {
        const bool ok = scheme_ok(dis_) && scheme_ok(ais_);
        estimates_result_ = ok ? RunStatus::kOk : RunStatus::kEstimatorFailed;
        if (design_.val_length > 0) {
          enter(Stage::kValidation);
        } else {
          finish(estimates_result_);
        }
      }
    }
    return true;
  }

  /// The validation phase: recorded by the host for `lashid diagnose`; nothing is estimated on the device.
  bool validation_sample() {
    float y = 0;
    if (!exchange(validation_.next(), y)) return true;
    if (++t_ == design_.val_length) finish(estimates_result_);
    return true;
  }

  /// Completes the reports once (cross-check, the board's figures), sends them, and starts holding them when the
  /// host asked for it with the start.
  void report() {
    cross_ = cross_check_of(dis_, ais_);
    // Optional board extensions (hal/board.hpp): a board that cannot tell does not model the concept.
    if constexpr (hal::ReportsStackUse<B>) {
      cost_.stack_bytes = static_cast<std::uint32_t>(board_.stack_high_water_bytes());
    }
    if constexpr (hal::ReportsExchangeErrors<B>) {
      cost_.link_errors += static_cast<std::uint32_t>(board_.exchange_errors());
      cost_.retries = static_cast<std::uint32_t>(board_.exchange_retries());
    }
    stage_ = Stage::kDone;
    send_reports();
    hold_start_ = board_.cycles();
  }

  /// Both records always go out; a scheme that never ran reports status kNotExcited. Sent again on kReport.
  void send_reports() {
    send_record(hal::link::MessageType::kEstimate, dis_);
    send_record(hal::link::MessageType::kEstimate, ais_);
    send_record(hal::link::MessageType::kCrossCheck, cross_);
    send_record(hal::link::MessageType::kCost, cost_);
    hal::link::PayloadWriter wd;
    wd.u8(static_cast<std::uint8_t>(result_));
    send(hal::link::MessageType::kDone, wd);
  }

  template <class Record>
  void send_record(hal::link::MessageType type, const Record& record) {
    hal::link::PayloadWriter w;
    record.encode(w);
    send(type, w);
  }

  /// Whether the run goes on holding its reports (kStartHoldReports, until kFinish or the hold time).
  bool holding() const {
    if constexpr (hal::KnowsCycleRate<B>) {
      constexpr std::uint32_t hold = B::kCyclesPerSecond * kReportHoldSeconds;
      static_assert(hold / kReportHoldSeconds == B::kCyclesPerSecond, "the hold time must fit 32-bit cycles");
      return hold_reports_ && board_.cycles() - hold_start_ < hold;
    } else {
      return false;
    }
  }

  void send(hal::link::MessageType type, const hal::link::PayloadWriter& w) { link_.send(type, w, cost_); }

  /// kStatus: the stage, samples exchanged so far, link errors. Sent on every stage change and on kQuery.
  void send_status() {
    hal::link::PayloadWriter w;
    w.u8(static_cast<std::uint8_t>(stage_));
    w.u32(cost_.samples);
    w.u32(cost_.link_errors);
    send(hal::link::MessageType::kStatus, w);
  }

  void on_design(const hal::link::Frame& f) {
    DesignStatus status = DesignStatus::kBusy;
    if (stage_ == Stage::kIdle && !started_) {
      RunDesign d;
      status = d.decode(f.reader());
      if (status == DesignStatus::kOk) {
        accept(d);
        status = design_status_;
      } else {
        design_status_ = status;
        design_ok_ = false;
        finish(RunStatus::kDesignRejected);
      }
    }
    hal::link::PayloadWriter w;
    w.u8(static_cast<std::uint8_t>(status));
    send(hal::link::MessageType::kDesignStatus, w);
  }

  void poll_link() {
    link_.poll(cost_, [this](const hal::link::Frame& f) {
      if (f.type == hal::link::MessageType::kDesign) on_design(f);
      if (f.type == hal::link::MessageType::kCommand) on_command(f);
    });
  }

  void on_command(const hal::link::Frame& f) {
    using hal::link::Command;
    if (f.size == 0) return;
    const auto command = static_cast<Command>(f.payload[0]);
    if (command == Command::kStart && f.size <= 2) {
      if (stage_ == Stage::kIdle && f.size == 2) {
        hold_reports_ = (f.payload[1] & hal::link::kStartHoldReports) != 0;
        samples_.start((f.payload[1] & hal::link::kStartStreamSamples) != 0);
      }
      started_ = true;
      return;
    }
    if (f.size != 1) return;
    switch (command) {
      case Command::kStart: break;
      case Command::kStop:
        if (stage_ != Stage::kDone && stage_ != Stage::kReport) finish(RunStatus::kStopped);
        break;
      case Command::kQuery: send_status(); break;
      case Command::kReport:
        if (stage_ == Stage::kDone && holding()) {
          send_reports();
          hold_start_ = board_.cycles();
        } else {
          send_status();
        }
        break;
      case Command::kFinish: hold_reports_ = false; break;
    }
  }

  B& board_;
  FramedLink<B> link_;
  bool started_ = false;
  bool design_ok_ = false;
  bool hold_reports_ = false;
  [[no_unique_address]] SampleStream<hal::BuffersLinkWrites<B>> samples_{};
  std::uint32_t hold_start_ = 0;
  DesignStatus design_status_ = DesignStatus::kMalformed;  // no design yet
  RunDesign design_{};
  Stage stage_ = Stage::kIdle;
  RunStatus result_ = RunStatus::kOk;
  RunStatus estimates_result_ = RunStatus::kOk;
  std::uint32_t t_ = 0;
  int phase_ = 0;  // t mod T in the pulse experiments
  Identifier identifier_{};
  est::ExcitationGenerator<float, N, M> generator_{Design{}, 1};
  ValidationExcitation validation_{};
  Estimate latest_{};  // the estimate of the current pulse period, updated in place
  EstimateRecord dis_ = not_run(est::Scheme::kDescending);
  EstimateRecord ais_ = not_run(est::Scheme::kAscending);
  est::StepMean<float> high_{};
  est::StepMean<float> low_{};
  CrossCheckRecord cross_{};
  CostRecord cost_{};
};

}  // namespace lashid::fw
