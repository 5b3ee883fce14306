// ExperimentConfig -> fw::RunDesign, and check_design()'s statuses in the words of the config file.
#include "lashid/hil/config_design.hpp"

#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "lashid/estimator/design.hpp"
#include "lashid/firmware/sequencer.hpp"
#include "lashid/hil/hil.hpp"
#include "lashid/io/data_error.hpp"

namespace lashid::sim {

// Every design the image runs can be identified and diagnosed from its recording on the host.
static_assert(kMaxOrder == fw::kMaxOrder && kMaxPoints == fw::kMaxPoints,
              "the host estimator's range (io/config.hpp) must be the firmware image's capacity (run_design.hpp)");

namespace {

// The firmware computes in float32; a double beyond its range would become infinite (and the conversion is
// undefined behaviour in C++), so it is refused here, naming the key.
float to_float(double value, std::string_view key, std::string_view source_name) {
  if (std::isfinite(value) && std::fabs(value) > static_cast<double>(std::numeric_limits<float>::max())) {
    throw DataError(source_name, fmt::format("'{}' = {} is beyond the range of float32, the firmware's arithmetic "
                                             "(at most {} in magnitude)",
                                             key, value, std::numeric_limits<float>::max()));
  }
  return static_cast<float>(value);
}

std::uint32_t to_count(int value, std::string_view key, std::string_view source_name) {
  if (value < 0) throw DataError(source_name, fmt::format("'{}' = {} must not be negative", key, value));
  return static_cast<std::uint32_t>(value);
}

void copy_levels(const std::vector<double>& from, std::string_view key, std::string_view source_name,
                 std::array<float, fw::kMaxPoints>& to) {
  for (std::size_t j = 0; j < from.size(); ++j) to[j] = to_float(from[j], fmt::format("{}[{}]", key, j), source_name);
}

// The first j whose level is not strictly beyond the one before it in the scheme's direction (float32).
int first_unordered(const std::array<float, fw::kMaxPoints>& V, int m, bool increasing) {
  for (int j = 1; j < m; ++j) {
    const float before = V[static_cast<std::size_t>(j - 1)];
    const float here = V[static_cast<std::size_t>(j)];
    if (increasing ? !(before < here) : !(before > here)) return j;
  }
  return 0;
}

}  // namespace

fw::RunDesign run_design_as_is(const ExperimentConfig& config, const ExperimentLengths& lengths,
                               std::string_view source_name) {
  for (const auto& [key, levels] : {std::pair{"V_d", &config.V_d}, std::pair{"V_a", &config.V_a}}) {
    if (levels->empty()) {
      throw DataError(source_name, fmt::format("'{}' is absent: a firmware run executes both schemes (the DIS, then "
                                               "the AIS) and needs both 'V_d' and 'V_a'",
                                               key));
    }
  }
  // The level arrays have kMaxPoints entries; n travels as one byte. check_design() names the capacity for n.
  if (config.m < 1 || config.m > fw::kMaxPoints) {
    throw DataError(source_name, fmt::format("'m' = {} is outside the firmware image's capacity [1, {}]", config.m,
                                             fw::kMaxPoints));
  }
  if (config.n < 1 || config.n > std::numeric_limits<std::uint8_t>::max()) {
    throw DataError(source_name, fmt::format("'n' = {} is outside the firmware image's capacity [1, {}]", config.n,
                                             fw::kMaxOrder));
  }
  fw::RunDesign d;
  d.op = config.op == OperatorKind::kSwitch ? fw::OperatorKind::kSwitch : fw::OperatorKind::kBacklash;
  d.n = static_cast<std::uint8_t>(config.n);
  d.m = static_cast<std::uint8_t>(config.m);
  d.v_min = to_float(config.v_min, "v_min", source_name);
  d.v_max = to_float(config.v_max, "v_max", source_name);
  copy_levels(config.V_d, "V_d", source_name, d.V_d);
  copy_levels(config.V_a, "V_a", source_name, d.V_a);
  d.step_length = to_count(lengths.step_length, "step_length", source_name);
  d.pulse_length_d = to_count(lengths.pulse_length_d, "pulse_length_d", source_name);
  d.pulse_length_a = to_count(lengths.pulse_length_a, "pulse_length_a", source_name);
  d.val_length = to_count(lengths.val_length, "val_length", source_name);
  d.val_seed = lengths.val_seed;
  if (config.sensor_range) {
    for (const double bound : *config.sensor_range) (void)to_float(bound, "sensor_range", source_name);  // in range
    // Rounded outwards (float32_sensor_range, which identify applies too): a value the host's double range allows is
    // never a bad value on the device.
    const auto [lo, hi] = float32_sensor_range(config);
    d.sensor_min = lo;
    d.sensor_max = hi;
  }
  return d;
}

fw::RunDesign to_run_design(const ExperimentConfig& config, std::string_view source_name) {
  const fw::RunDesign d = run_design_as_is(config, experiment_lengths(config), source_name);
  if (const fw::DesignStatus status = fw::check_design(d); status != fw::DesignStatus::kOk) {
    throw DataError(source_name, fmt::format("the firmware image cannot run this design: {} (firmware status: {})",
                                             design_status_message(status, d), fw::to_string(status)));
  }
  return d;
}

std::string design_status_message(fw::DesignStatus status, const fw::RunDesign& d) {
  using S = fw::DesignStatus;
  const int last = d.m - 1;
  const auto level = [](const std::array<float, fw::kMaxPoints>& V, int j) { return V[static_cast<std::size_t>(j)]; };
  // Messages quote the float32 values the firmware compares: the rules may hold in double and fail only there.
  switch (status) {
    case S::kOk: return {};
    case S::kMalformed: return "the design message is malformed (wrong length for m, or unknown bytes)";
    case S::kBusy: return "a run is under way: its design cannot change";
    case S::kOutsideActuatorRange:
      return fmt::format("['v_min', 'v_max'] = [{}, {}] reaches beyond the board's actuator range (what its DAC "
                         "reaches in the design's units: the image's LASHID_ANALOG_* settings)",
                         d.v_min, d.v_max);
    case S::kUnknownOperator: return "'operator' must be \"switch\" or \"backlash\"";
    case S::kOrderOutOfRange:
      return fmt::format("'n' = {} is outside the firmware image's capacity [1, {}]", d.n, fw::kMaxOrder);
    case S::kPointsOutOfRange:
      return fmt::format("'m' = {} is outside the firmware image's capacity [1, {}]", d.m, fw::kMaxPoints);
    case S::kIntervalInvalid:
      return fmt::format("'v_max' = {} is not above 'v_min' = {} in float32, the firmware's arithmetic", d.v_max,
                         d.v_min);
    case S::kLevelNotFinite: return "a level of 'V_d' or 'V_a' is not finite in float32";
    case S::kVdFirstNotVMin:
      return fmt::format("'V_d[0]' = {} must equal 'v_min' = {} (3.1)", level(d.V_d, 0), d.v_min);
    case S::kVdNotIncreasing: {
      const int j = first_unordered(d.V_d, d.m, true);
      return fmt::format("in float32 'V_d[{}]' = {} is not greater than 'V_d[{}]' = {} (V_d strictly increasing, "
                         "(3.1)): the two levels are too close for the firmware",
                         j, level(d.V_d, j), j - 1, level(d.V_d, j - 1));
    }
    case S::kVdNotBelowVMax:
      return fmt::format("in float32 'V_d[{}]' = {} is not below 'v_max' = {} (3.1)", last, level(d.V_d, last),
                         d.v_max);
    case S::kVaFirstNotVMax:
      return fmt::format("'V_a[0]' = {} must equal 'v_max' = {} (4.2)", level(d.V_a, 0), d.v_max);
    case S::kVaNotDecreasing: {
      const int j = first_unordered(d.V_a, d.m, false);
      return fmt::format("in float32 'V_a[{}]' = {} is not less than 'V_a[{}]' = {} (V_a strictly decreasing, "
                         "(4.2)): the two levels are too close for the firmware",
                         j, level(d.V_a, j), j - 1, level(d.V_a, j - 1));
    }
    case S::kVaNotAboveVMin:
      return fmt::format("in float32 'V_a[{}]' = {} is not above 'v_min' = {} (4.2)", last, level(d.V_a, last),
                         d.v_min);
    case S::kLevelsTooClose: {
      // The firmware's own test, applied to one scheme at a time to name the key.
      const bool d_distinct = est::levels_resolvable(d.V_d.data(), d.m, d.v_max);
      const auto& V = d_distinct ? d.V_a : d.V_d;
      const float held = d_distinct ? d.v_min : d.v_max;
      for (int j = 0; j < d.m; ++j) {
        // Near float32's range the same test fails for the opposite reason: a step V_j - held overflows.
        if (!std::isfinite(level(V, j) - held)) {
          return fmt::format("'{}[{}]' = {} minus the held level '{}' = {} overflows float32: the interval is too "
                             "wide for the firmware (|V_j - held| must stay below 3.4e38)",
                             d_distinct ? "V_a" : "V_d", j, level(V, j), d_distinct ? "v_min" : "v_max", held);
        }
      }
      return fmt::format("'{}': two levels, or a level and the held level {}, are closer than the firmware's float32 "
                         "classifier resolves (2 x 64 eps of the largest |V_j - held|); it could not tell them apart",
                         d_distinct ? "V_a" : "V_d", d_distinct ? "v_min" : "v_max");
    }
    case S::kStepTooShort:
      return fmt::format("'step_length' = {} must be greater than n = {} (the step experiment's mean (3.7) needs L > n)",
                         d.step_length, d.n);
    case S::kPulseDTooShort:
    case S::kPulseATooShort: {
      const bool dis = status == S::kPulseDTooShort;
      return fmt::format("'{}' = {} is shorter than two pulse periods (2T = {} for n = {}, m = {})",
                         dis ? "pulse_length_d" : "pulse_length_a", dis ? d.pulse_length_d : d.pulse_length_a,
                         2 * d.period(), d.n, d.m);
    }
    case S::kSensorRangeInvalid:
      return fmt::format("'sensor_range' = [{}, {}] must have lo < hi", d.sensor_min, d.sensor_max);
    case S::kPulseTooLong: {
      const bool dis = d.pulse_length_d > est::kMaxPulseLength;
      return fmt::format("'{}' = {} is longer than the float32 estimator is accurate for (at most {} samples: its "
                         "sums lose accuracy beyond, docs/estimator.md)",
                         dis ? "pulse_length_d" : "pulse_length_a", dis ? d.pulse_length_d : d.pulse_length_a,
                         est::kMaxPulseLength);
    }
    case S::kRunTooLong:
      return fmt::format("the run does not fit the firmware's 32-bit sample counter (at most {} samples with the "
                         "interval check): shorten 'step_length', 'pulse_length_d', 'pulse_length_a' or 'val_length'",
                         std::numeric_limits<std::uint32_t>::max());
  }
  return fmt::format("unknown design status {}", static_cast<int>(status));
}

FirmwareRunSamples firmware_run_samples(const fw::RunDesign& d) {
  FirmwareRunSamples samples;
  samples.interval_check = d.interval_check_samples();
  samples.steps = 2 * (std::uint64_t{d.step_length} + 1);
  samples.pulses = std::uint64_t{d.pulse_length_d} + d.pulse_length_a;
  samples.validation = d.val_length;
  return samples;
}

}  // namespace lashid::sim
