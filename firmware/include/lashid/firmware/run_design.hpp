// The design of one identification run, chosen at run time: what the host sends with the start of a run (kDesign)
// and what one firmware image executes, within the image's compile-time capacity (kMaxOrder, kMaxPoints).
//   operator, n, m, [v_m, v_M], V^d (3.1), V^a (4.2), L of both step experiments (3.4)/(4.1), N of the DP and AP
//   pulse experiments, the length and seed of the validation phase, and the sensor's range (a value outside it is a
//   bad sensor value: counted, never estimated from).
// check_design() applies the paper's design rules at run time and names the first one violated; the firmware runs
// nothing on a design that fails it, and the host's `lashid design` applies the same function to a config file.
// Header-only, heap-free, float32 as the firmware computes.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "lashid/estimator/design.hpp"
#include "lashid/hal/link_protocol.hpp"

namespace lashid::fw {

namespace detail {
// A constant-expression form of isfinite: the rules are checked at compile time on the paper's designs
// (paper_run_designs.hpp), and libstdc++'s <cmath> functions are constexpr only as GCC builtins, not under Clang.
constexpr bool finite(float x) {
  return x == x && x != std::numeric_limits<float>::infinity() && x != -std::numeric_limits<float>::infinity();
}
}  // namespace detail

/// Capacity of the firmware image: fixed-size storage for models up to this order and points per border. The
/// estimate record of the largest design must fit one link frame (static_assert in messages.hpp).
inline constexpr int kMaxOrder = 4;
inline constexpr int kMaxPoints = 10;

/// Interval check (Section 3.4 step 1, backlash only): a square wave v_M / v_m of half-period 2T for this many periods.
inline constexpr int kIntervalCheckPeriods = 4;

/// The nonlinearity the actuator is assumed to have: a backlash needs the interval check (Section 3.4 step 1).
enum class OperatorKind : std::uint8_t { kSwitch = 0, kBacklash = 1 };

/// Why a design was refused; kOk when every rule holds. One status per rule, checked in this order.
enum class [[nodiscard]] DesignStatus : std::uint8_t {
  kOk = 0,
  kMalformed,           ///< the kDesign payload has the wrong length or unknown bytes
  kUnknownOperator,     ///< operator is neither switch (0) nor backlash (1)
  kOrderOutOfRange,     ///< n < 1 or n > kMaxOrder
  kPointsOutOfRange,    ///< m < 1 or m > kMaxPoints
  kIntervalInvalid,     ///< v_m, v_M not finite or v_m >= v_M
  kLevelNotFinite,      ///< some V_j^d or V_j^a is NaN or infinite
  kVdFirstNotVMin,      ///< (3.1): V_1^d must equal v_m
  kVdNotIncreasing,     ///< (3.1): V_1^d < V_2^d < ... < V_m^d
  kVdNotBelowVMax,      ///< (3.1): V_m^d < v_M
  kVaFirstNotVMax,      ///< (4.2): V_1^a must equal v_M
  kVaNotDecreasing,     ///< (4.2): V_1^a > V_2^a > ... > V_m^a
  kVaNotAboveVMin,      ///< (4.2): V_m^a > v_m
  kLevelsTooClose,      ///< two pulse levels (or a level and the held one) closer than float32 can tell apart, or
                        ///< a level so far from the held one that the step overflows float32
  kStepTooShort,        ///< L <= n: the step experiment's mean (3.7) needs L > n
  kPulseDTooShort,      ///< N of the DP experiment < two pulse periods 2T, T = s (m + 3) (Theorem 3.1)
  kPulseATooShort,      ///< N of the AP experiment < 2T
  kRunTooLong,          ///< the samples of the whole run do not fit the firmware's 32-bit counters
  kSensorRangeInvalid,  ///< the sensor range is NaN or empty (need sensor_min < sensor_max; infinite bounds allowed)
  kBusy,                ///< a design arrived after the start: a run's design cannot change (the run goes on)
  // Added after the others so that the codes above keep their values on the link; checked after kPulseATooShort.
  kPulseTooLong,        ///< N of a pulse experiment > est::kMaxPulseLength: float32's sums would lose accuracy
  /// [v_min, v_max] reaches beyond the board's actuator range (hal::LimitsActuatorRange: what a DAC reaches, in the
  /// design's units); checked by the sequencer after check_design, for a board that has one.
  kOutsideActuatorRange,
};

constexpr const char* to_string(DesignStatus s) {
  switch (s) {
    case DesignStatus::kOk: return "ok";
    case DesignStatus::kMalformed: return "malformed design message";
    case DesignStatus::kUnknownOperator: return "operator must be switch or backlash";
    case DesignStatus::kOrderOutOfRange: return "n outside the image's capacity [1, 4]";
    case DesignStatus::kPointsOutOfRange: return "m outside the image's capacity [1, 10]";
    case DesignStatus::kIntervalInvalid: return "working interval invalid (need finite v_min < v_max)";
    case DesignStatus::kLevelNotFinite: return "a level of V_d or V_a is not finite";
    case DesignStatus::kVdFirstNotVMin: return "(3.1): V_d[0] must equal v_min";
    case DesignStatus::kVdNotIncreasing: return "(3.1): V_d must be strictly increasing";
    case DesignStatus::kVdNotBelowVMax: return "(3.1): the last V_d must be below v_max";
    case DesignStatus::kVaFirstNotVMax: return "(4.2): V_a[0] must equal v_max";
    case DesignStatus::kVaNotDecreasing: return "(4.2): V_a must be strictly decreasing";
    case DesignStatus::kVaNotAboveVMin: return "(4.2): the last V_a must be above v_min";
    case DesignStatus::kLevelsTooClose:
      return "two levels closer than float32 resolves (2 x 64 eps of the largest step), or a step that overflows float32";
    case DesignStatus::kStepTooShort: return "step_length must exceed n (3.7)";
    case DesignStatus::kPulseDTooShort: return "pulse_length_d shorter than two pulse periods (Theorem 3.1)";
    case DesignStatus::kPulseATooShort: return "pulse_length_a shorter than two pulse periods (Theorem 3.1)";
    case DesignStatus::kRunTooLong: return "the run's sample count does not fit 32 bits";
    case DesignStatus::kSensorRangeInvalid: return "sensor range invalid (need sensor_min < sensor_max)";
    case DesignStatus::kBusy: return "a run is under way: its design cannot change";
    case DesignStatus::kPulseTooLong: return "a pulse length beyond 2^28 samples (float32 accuracy)";
    case DesignStatus::kOutsideActuatorRange: return "the working interval reaches beyond the board's actuator range";
  }
  return "unknown design status";
}

/// Both schemes' experiments plus the validation phase, as one firmware run executes them.
struct RunDesign {
  OperatorKind op = OperatorKind::kSwitch;
  std::uint8_t n = 0;
  std::uint8_t m = 0;
  float v_min = 0;
  float v_max = 0;
  std::array<float, kMaxPoints> V_d{};  ///< V_1^d .. V_m^d (entries past m unused)
  std::array<float, kMaxPoints> V_a{};  ///< V_1^a .. V_m^a
  std::uint32_t step_length = 0;        ///< L: each step experiment has L + 1 samples, t = 0..L
  std::uint32_t pulse_length_d = 0;     ///< N of the DP experiment
  std::uint32_t pulse_length_a = 0;     ///< N of the AP experiment
  std::uint32_t val_length = 0;         ///< samples of the validation phase (0: none)
  std::uint32_t val_seed = 0;           ///< seed of the validation excitation
  /// The sensor's range: a measured y outside [sensor_min, sensor_max] (or not finite) is a bad sensor value.
  float sensor_min = -std::numeric_limits<float>::infinity();
  float sensor_max = std::numeric_limits<float>::infinity();

  /// Whether a measured value can be estimated from: finite and within the sensor's range.
  constexpr bool sensor_value_ok(float y) const { return detail::finite(y) && y >= sensor_min && y <= sensor_max; }

  /// Pulse period T of Theorem 3.1 (3.25) for this n, m.
  constexpr int period() const { return est::schedule::period(n, m); }
  /// Whether the run starts with the interval check of Section 3.4 step 1 (backlash only).
  constexpr bool checks_interval() const { return op == OperatorKind::kBacklash; }
  /// Samples of the interval check: kIntervalCheckPeriods periods of two half-periods of 2T, or 0.
  constexpr std::uint64_t interval_check_samples() const {
    return checks_interval() ? std::uint64_t{kIntervalCheckPeriods} * 2U * 2U * static_cast<std::uint64_t>(period())
                             : 0U;
  }

  /// Payload bytes of kDesign for m points: op, n, m (u8); v_min, v_max (f32); five lengths (u32); sensor_min,
  /// sensor_max (f32); V_d, V_a.
  static constexpr std::size_t encoded_size(int points) {
    return 3 + 2 * 4 + 5 * 4 + 2 * 4 + 2 * 4 * static_cast<std::size_t>(points);
  }

  void encode(hal::link::PayloadWriter& w) const {
    w.u8(static_cast<std::uint8_t>(op));
    w.u8(n);
    w.u8(m);
    w.f32(v_min);
    w.f32(v_max);
    for (std::uint32_t x : {step_length, pulse_length_d, pulse_length_a, val_length, val_seed}) w.u32(x);
    w.f32(sensor_min);
    w.f32(sensor_max);
    for (int j = 0; j < m && j < kMaxPoints; ++j) w.f32(V_d[static_cast<std::size_t>(j)]);
    for (int j = 0; j < m && j < kMaxPoints; ++j) w.f32(V_a[static_cast<std::size_t>(j)]);
  }

  /// Reads a kDesign payload. kMalformed when the length does not match m; kPointsOutOfRange when m exceeds the
  /// capacity (its arrays are then not read); the rules themselves are check_design()'s.
  DesignStatus decode(hal::link::PayloadReader r) {
    const std::uint8_t op_byte = r.u8();
    n = r.u8();
    m = r.u8();
    if (!r.ok()) return DesignStatus::kMalformed;
    if (m > kMaxPoints) return DesignStatus::kPointsOutOfRange;
    op = static_cast<OperatorKind>(op_byte);
    v_min = r.f32();
    v_max = r.f32();
    for (std::uint32_t* x : {&step_length, &pulse_length_d, &pulse_length_a, &val_length, &val_seed}) *x = r.u32();
    sensor_min = r.f32();
    sensor_max = r.f32();
    for (int j = 0; j < m; ++j) V_d[static_cast<std::size_t>(j)] = r.f32();
    for (int j = 0; j < m; ++j) V_a[static_cast<std::size_t>(j)] = r.f32();
    if (!r.ok() || !r.at_end()) return DesignStatus::kMalformed;
    return op_byte <= 1 ? DesignStatus::kOk : DesignStatus::kUnknownOperator;
  }
};

static_assert(RunDesign::encoded_size(kMaxPoints) <= hal::link::kMaxPayload,
              "a design of the image's capacity must fit one link frame");

/// The paper's design rules and the image's capacity, first violation first (the order of DesignStatus).
constexpr DesignStatus check_design(const RunDesign& d) {
  if (d.op != OperatorKind::kSwitch && d.op != OperatorKind::kBacklash) return DesignStatus::kUnknownOperator;
  if (d.n < 1 || d.n > kMaxOrder) return DesignStatus::kOrderOutOfRange;
  if (d.m < 1 || d.m > kMaxPoints) return DesignStatus::kPointsOutOfRange;
  if (!detail::finite(d.v_min) || !detail::finite(d.v_max) || !(d.v_min < d.v_max)) {
    return DesignStatus::kIntervalInvalid;
  }
  const auto m = static_cast<std::size_t>(d.m);
  for (std::size_t j = 0; j < m; ++j) {
    if (!detail::finite(d.V_d[j]) || !detail::finite(d.V_a[j])) return DesignStatus::kLevelNotFinite;
  }
  if (d.V_d[0] != d.v_min) return DesignStatus::kVdFirstNotVMin;
  for (std::size_t j = 1; j < m; ++j) {
    if (!(d.V_d[j - 1] < d.V_d[j])) return DesignStatus::kVdNotIncreasing;
  }
  if (!(d.V_d[m - 1] < d.v_max)) return DesignStatus::kVdNotBelowVMax;
  if (d.V_a[0] != d.v_max) return DesignStatus::kVaFirstNotVMax;
  for (std::size_t j = 1; j < m; ++j) {
    if (!(d.V_a[j - 1] > d.V_a[j])) return DesignStatus::kVaNotDecreasing;
  }
  if (!(d.V_a[m - 1] > d.v_min)) return DesignStatus::kVaNotAboveVMin;
  if (!est::levels_resolvable(d.V_d.data(), d.m, d.v_max) || !est::levels_resolvable(d.V_a.data(), d.m, d.v_min)) {
    return DesignStatus::kLevelsTooClose;
  }
  if (d.step_length <= d.n) return DesignStatus::kStepTooShort;
  const auto two_periods = static_cast<std::uint32_t>(2 * d.period());
  if (d.pulse_length_d < two_periods) return DesignStatus::kPulseDTooShort;
  if (d.pulse_length_a < two_periods) return DesignStatus::kPulseATooShort;
  if (d.pulse_length_d > est::kMaxPulseLength || d.pulse_length_a > est::kMaxPulseLength) {
    return DesignStatus::kPulseTooLong;
  }
  // Interval check, two step phases (L + 1 each), two pulse phases and the validation: all in one u32 counter (the
  // interval check counted whatever the operator, so that the limit does not depend on it).
  const std::uint64_t check = std::uint64_t{kIntervalCheckPeriods} * 2U * 2U * static_cast<std::uint64_t>(d.period());
  const std::uint64_t total =
      check + 2ULL * (d.step_length + 1ULL) + d.pulse_length_d + d.pulse_length_a + d.val_length;
  if (total > std::numeric_limits<std::uint32_t>::max()) return DesignStatus::kRunTooLong;
  if (!(d.sensor_min < d.sensor_max)) return DesignStatus::kSensorRangeInvalid;
  return DesignStatus::kOk;
}

}  // namespace lashid::fw
