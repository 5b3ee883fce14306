// Payloads of the firmware's reports over the link (hal/link_protocol.hpp), encoded by the firmware and decoded by
// the host tool and the tests. Fixed-size records, no heap.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "lashid/estimator/design.hpp"
#include "lashid/firmware/run_design.hpp"
#include "lashid/hal/link_protocol.hpp"

namespace lashid::fw {

/// The records hold what the image can estimate (run_design.hpp's capacity).
inline constexpr int kMaxRecordOrder = kMaxOrder;
inline constexpr int kMaxRecordPoints = kMaxPoints;

/// Stages of the identification sequence, as reported in kStatus.
enum class Stage : std::uint8_t {
  kIdle = 0,
  kIntervalCheck,
  kStepD,
  kPulseD,
  kStepA,
  kPulseA,
  kValidation,
  kReport,
  kDone,
};

/// Freestanding (no heap): a string literal, for the host's printing and the tests.
constexpr const char* to_string(Stage s) {
  switch (s) {
    case Stage::kIdle: return "idle";
    case Stage::kIntervalCheck: return "interval check";
    case Stage::kStepD: return "DIS step experiment";
    case Stage::kPulseD: return "DP pulse experiment";
    case Stage::kStepA: return "AIS step experiment";
    case Stage::kPulseA: return "AP pulse experiment";
    case Stage::kValidation: return "validation";
    case Stage::kReport: return "report";
    case Stage::kDone: return "done";
  }
  return "unknown stage";
}

/// Overall result of a run (kDone payload).
enum class RunStatus : std::uint8_t {
  kOk = 0,
  kIntervalTooNarrow,  ///< Section 3.4 step 1: the output does not follow v_m <-> v_M (Fig. 5); enlarge it
  kActuatorFault,      ///< the board rejected a command
  kSensorFault,        ///< a measurement could not be obtained after retries, or the interval check had fewer
                       ///< than two usable readings at v_m or at v_M (every one NaN, clipped or out of range)
  kEstimatorFailed,    ///< a scheme's estimate has a non-ok status (see its kEstimate record)
  kStopped,            ///< stopped by command
  kDesignRejected,     ///< the design sent with kDesign broke a rule (its DesignStatus was answered); nothing ran
};

constexpr const char* to_string(RunStatus s) {
  switch (s) {
    case RunStatus::kOk: return "ok";
    case RunStatus::kIntervalTooNarrow: return "interval too narrow";
    case RunStatus::kActuatorFault: return "actuator fault";
    case RunStatus::kSensorFault: return "sensor fault";
    case RunStatus::kEstimatorFailed: return "estimator failed";
    case RunStatus::kStopped: return "stopped";
    case RunStatus::kDesignRejected: return "design rejected";
  }
  return "unknown";
}

/// The scheme of an EstimateRecord on the wire: one byte, est::Scheme's value (0 = DIS, 1 = AIS).
constexpr bool valid_scheme_byte(std::uint8_t b) {
  return b == static_cast<std::uint8_t>(est::Scheme::kDescending) ||
         b == static_cast<std::uint8_t>(est::Scheme::kAscending);
}

/// One scheme's estimate (kEstimate). Arrays hold n (a, b and their standard errors) and m (F) entries.
struct EstimateRecord {
  /// Payload bytes for orders n, m: scheme, status, n, m (u8), ybar0, noise variance, 4 n + m floats.
  static constexpr std::size_t encoded_size(int n, int m) {
    return 4 + 4 * (2 + 4 * static_cast<std::size_t>(n) + static_cast<std::size_t>(m));
  }

  est::Scheme scheme = est::Scheme::kDescending;  ///< one byte on the wire (valid_scheme_byte)
  std::uint8_t status = 0;  ///< est::Status
  std::uint8_t n = 0;
  std::uint8_t m = 0;
  float ybar0 = 0;
  float noise_variance = 0;
  std::array<float, kMaxRecordOrder> a{}, se_a{}, b{}, se_b{};
  std::array<float, kMaxRecordPoints> F{};

  void encode(hal::link::PayloadWriter& w) const {
    w.u8(static_cast<std::uint8_t>(scheme));
    w.u8(status);
    w.u8(n);
    w.u8(m);
    w.f32(ybar0);
    w.f32(noise_variance);
    for (int i = 0; i < n; ++i) {
      const auto k = static_cast<std::size_t>(i);
      w.f32(a[k]);
      w.f32(se_a[k]);
      w.f32(b[k]);
      w.f32(se_b[k]);
    }
    for (int j = 0; j < m; ++j) w.f32(F[static_cast<std::size_t>(j)]);
  }

  bool decode(hal::link::PayloadReader r) {
    const std::uint8_t scheme_byte = r.u8();
    status = r.u8();
    n = r.u8();
    m = r.u8();
    if (!valid_scheme_byte(scheme_byte) || n > kMaxRecordOrder || m > kMaxRecordPoints) return false;
    scheme = static_cast<est::Scheme>(scheme_byte);
    ybar0 = r.f32();
    noise_variance = r.f32();
    for (int i = 0; i < n; ++i) {
      const auto k = static_cast<std::size_t>(i);
      a[k] = r.f32();
      se_a[k] = r.f32();
      b[k] = r.f32();
      se_b[k] = r.f32();
    }
    for (int j = 0; j < m; ++j) F[static_cast<std::size_t>(j)] = r.f32();
    return r.ok() && r.at_end();
  }
};

/// Remark 3b (kCrossCheck): the DIS and AIS estimate the same linear subsystem; a disagreement beyond their
/// uncertainty means the nonlinearity is not the assumed switch/backlash.
struct CrossCheckRecord {
  static constexpr std::size_t kEncodedSize = 2 + 2 * 4;
  std::uint8_t disagree = 0;   ///< 1 if max_z exceeds the configured threshold
  std::uint8_t worst = 0;      ///< index of the worst parameter: 0..n-1 = a_i, n..2n-1 = b_i
  float max_z = 0;             ///< max |x_dis - x_ais| / sqrt(se_dis^2 + se_ais^2) over a and b
  float threshold = 0;

  void encode(hal::link::PayloadWriter& w) const {
    w.u8(disagree);
    w.u8(worst);
    w.f32(max_z);
    w.f32(threshold);
  }
  bool decode(hal::link::PayloadReader r) {
    disagree = r.u8();
    worst = r.u8();
    max_z = r.f32();
    threshold = r.f32();
    return r.ok() && r.at_end();
  }
};

/// Footprint and cost (kCost), in board cycles (SysTick on Cortex-M), and what went wrong without ending the run.
struct CostRecord {
  static constexpr std::size_t kEncodedSize = 2 * 8 + 9 * 4;
  /// Total over all estimator updates (add_pulse_sample). 64 bits: at ~300 cycles per update a 32-bit total wraps
  /// after ~14 million samples, and a run may have up to 2^28 per pulse experiment (kPulseTooLong).
  std::uint64_t update_cycles = 0;
  std::uint32_t updates = 0;
  std::uint64_t solve_cycles = 0;   ///< total over all estimate() calls (once per pulse period); 64 bits as above
  std::uint32_t solves = 0;
  std::uint32_t samples = 0;        ///< samples exchanged with the plant
  std::uint32_t link_errors = 0;    ///< frames dropped (checksum/length) or stale, on either port
  std::uint32_t retries = 0;        ///< actuator/sensor exchanges repeated after a loss
  std::uint32_t stack_bytes = 0;    ///< stack high-water mark (0 where the board cannot tell)
  /// Step and pulse samples the estimator refused (non-ok status: non-finite, off the design); they are not in
  /// the estimate, which stays the least squares on the samples used.
  std::uint32_t rejected_samples = 0;
  /// Reports not sent because their payload did not fit a frame (the records before this one; none can, by the
  /// sequencer's static_asserts, so anything but 0 is a defect).
  std::uint32_t send_failures = 0;
  /// Sensor values that were NaN, infinite or outside the design's sensor range: counted and never estimated from
  /// (the rows that hold one are among rejected_samples).
  std::uint32_t bad_sensor_values = 0;

  void encode(hal::link::PayloadWriter& w) const {
    w.u64(update_cycles);
    w.u32(updates);
    w.u64(solve_cycles);
    for (std::uint32_t x : {solves, samples, link_errors, retries, stack_bytes, rejected_samples, send_failures,
                            bad_sensor_values})
      w.u32(x);
  }
  bool decode(hal::link::PayloadReader r) {
    update_cycles = r.u64();
    updates = r.u32();
    solve_cycles = r.u64();
    for (std::uint32_t* x : {&solves, &samples, &link_errors, &retries, &stack_bytes, &rejected_samples,
                             &send_failures, &bad_sensor_values})
      *x = r.u32();
    return r.ok() && r.at_end();
  }
};

/// Consecutive samples of a run as the board measured them (kSamples, with kStartStreamSamples): the command v and
/// the measured y of the run's samples first .. first + count - 1 (the run's sample index: samples exchanged before
/// it, interval check included), y as measured, and which of them the firmware set aside as bad sensor values (bit k
/// of set_aside: a clipped or out-of-range reading, left out of the estimates).
struct SampleBlock {
  /// 4 + 1 + 2 + 14 x 8 = 119 bytes of the 128 a frame holds.
  static constexpr std::size_t kCapacity = 14;
  std::uint32_t first = 0;
  std::uint8_t count = 0;
  std::uint16_t set_aside = 0;
  std::array<float, kCapacity> v{};
  std::array<float, kCapacity> y{};

  static constexpr std::size_t encoded_size(std::size_t count) { return 4 + 1 + 2 + 8 * count; }
  bool full() const { return count == kCapacity; }
  /// Appends sample `index`; the first of a block sets `first`. The caller sends a full block before the next.
  void add(std::uint32_t index, float v_sample, float y_sample, bool bad) {
    if (count == 0) {
      first = index;
      set_aside = 0;
    }
    v[count] = v_sample;
    y[count] = y_sample;
    if (bad) set_aside = static_cast<std::uint16_t>(set_aside | (1U << count));
    ++count;
  }
  void encode(hal::link::PayloadWriter& w) const {
    w.u32(first);
    w.u8(count);
    w.u16(set_aside);
    for (std::size_t k = 0; k < count; ++k) {
      w.f32(v[k]);
      w.f32(y[k]);
    }
  }
  bool decode(hal::link::PayloadReader r) {
    first = r.u32();
    count = r.u8();
    set_aside = r.u16();
    if (count == 0 || count > kCapacity || (set_aside >> count) != 0U) return false;
    for (std::size_t k = 0; k < count; ++k) {
      v[k] = r.f32();
      y[k] = r.f32();
    }
    return r.ok() && r.at_end();
  }
};

static_assert(SampleBlock::encoded_size(SampleBlock::kCapacity) <= hal::link::kMaxPayload);
static_assert(EstimateRecord::encoded_size(kMaxRecordOrder, kMaxRecordPoints) <= hal::link::kMaxPayload,
              "the estimate of the largest design the image accepts must fit one link frame");
static_assert(CrossCheckRecord::kEncodedSize <= hal::link::kMaxPayload);
static_assert(CostRecord::kEncodedSize <= hal::link::kMaxPayload);

}  // namespace lashid::fw
