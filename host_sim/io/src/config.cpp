// Whether a recording fits an experiment config (levels, schemes, lengths), and the operator names.
#include "lashid/io/config.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "lashid/estimator/design.hpp"

namespace lashid::sim {

std::string_view to_string(OperatorKind kind) { return kind == OperatorKind::kSwitch ? "switch" : "backlash"; }

int default_pulse_length(int n, int m) {
  const int period = est::schedule::period(n, m);
  const int periods = std::max(2, (kDefaultPulseSamples + period - 1) / period);  // ceil, and at least 2T
  return periods * period;
}

ExperimentLengths experiment_lengths(const ExperimentConfig& config) {
  const int pulse_default = default_pulse_length(config.n, config.m);
  return {.step_length = config.step_length.value_or(kDefaultStepLength),
          .pulse_length_d = config.pulse_length_d.value_or(pulse_default),
          .pulse_length_a = config.pulse_length_a.value_or(pulse_default),
          .val_length = config.val_length.value_or(kDefaultValLength),
          .val_seed = config.val_seed.value_or(kDefaultValSeed)};
}

namespace {

// The levels an identification phase may apply: the paper's step (3.4)/(4.1) and pulse (3.1)/(4.2) inputs.
std::vector<double> allowed_levels(const ExperimentConfig& config, Phase phase) {
  std::vector<double> levels;
  switch (phase) {
    case Phase::kStepD:
    case Phase::kStepA:
      levels = {config.v_min, config.v_max};
      break;
    case Phase::kDis:
      levels = config.V_d;
      levels.push_back(config.v_max);
      break;
    case Phase::kAis:
      levels = config.V_a;
      levels.push_back(config.v_min);
      break;
    case Phase::kVal:
      break;
  }
  return levels;
}

}  // namespace

double level_tolerance(const ExperimentConfig& config) {
  // Two things a recorded level may differ by: a float32 device's rounding of it (at most half a float32 ulp of the
  // largest |v|, and eps32 |v| / 2 bounds that), and the firmware classifier's resolution, relative to the interval
  // (est::LagrangeBasis works on v - held: kLevelResolution x the width). Not kLevelResolution x |v|: on an interval
  // far from 0 ([1e6, 1e6 + 1]) that was 7.6, wider than the interval, and every off-design v matched some level.
  const double magnitude = std::max(std::fabs(config.v_min), std::fabs(config.v_max));
  constexpr double kEps32 = static_cast<double>(std::numeric_limits<float>::epsilon());
  return std::max(0.5 * kEps32 * magnitude,
                  static_cast<double>(est::kLevelResolution<float>) * (config.v_max - config.v_min));
}

std::array<float, 2> float32_sensor_range(const ExperimentConfig& config) {
  constexpr float kInf = std::numeric_limits<float>::infinity();
  if (!config.sensor_range) return {-kInf, kInf};
  const auto as_float = [](double x) {
    // Beyond float32's range: infinite with its sign (a plain conversion would be undefined behaviour).
    if (std::fabs(x) > static_cast<double>(std::numeric_limits<float>::max())) return x > 0 ? kInf : -kInf;
    return static_cast<float>(x);
  };
  return {std::nextafter(as_float((*config.sensor_range)[0]), -kInf),
          std::nextafter(as_float((*config.sensor_range)[1]), kInf)};
}

Recording snap_to_configured_levels(const ExperimentConfig& config, const Recording& recording) {
  const double tolerance = level_tolerance(config);
  Recording out;
  for (const Phase phase : recording.order()) {
    const std::vector<double> levels = phase == Phase::kVal ? std::vector<double>{} : allowed_levels(config, phase);
    for (const Sample& x : recording.phase(phase)) {
      double v = x.v;
      double best = tolerance;
      for (const double level : levels) {  // the nearest level within the tolerance, if any
        if (std::fabs(x.v - level) <= best) {
          best = std::fabs(x.v - level);
          v = level;
        }
      }
      out.append(phase, v, x.y);
    }
  }
  return out;
}

void check_recording_matches(const ExperimentConfig& config, const Recording& recording, std::string_view data_name) {
  const auto fail = [&](std::string_view message) { throw DataError(data_name, message); };
  const auto n = static_cast<std::size_t>(config.n);
  // A level matches within level_tolerance(): text conversions and a float32 device's rounding of the levels
  // (snap_to_configured_levels then hands the estimator the configured levels themselves).
  const double tolerance = level_tolerance(config);
  const auto matches = [tolerance](double v, double level) { return std::fabs(v - level) <= tolerance; };
  // Two periods of the estimator's schedule (spacing max(n, 2), see est::schedule) are the least that shows every
  // level after a full period.
  const auto pulse_minimum = static_cast<std::size_t>(2 * est::schedule::period(config.n, config.m));
  for (const Phase phase : recording.order()) {
    if (phase == Phase::kVal) continue;  // validation data may use any input
    const std::string_view name = to_string(phase);
    if (phase == Phase::kDis && config.V_d.empty()) {
      fail("phase 'dis' is recorded but the config has no 'V_d' (the DIS needs its pulse levels)");
    }
    if (phase == Phase::kAis && config.V_a.empty()) {
      fail("phase 'ais' is recorded but the config has no 'V_a' (the AIS needs its pulse levels)");
    }

    const std::span<const Sample> samples = recording.phase(phase);
    const std::vector<double> levels = allowed_levels(config, phase);
    for (std::size_t t = 0; t < samples.size(); ++t) {
      const double v = samples[t].v;
      if (v < config.v_min - tolerance || v > config.v_max + tolerance) {
        fail(fmt::format("phase '{}' t = {}: v = {} is outside [v_min, v_max] = [{}, {}]", name, t, v, config.v_min,
                         config.v_max));
      }
      // The estimator treats the border as static only because the input visits these exact levels.
      if (std::none_of(levels.begin(), levels.end(), [&](double level) { return matches(v, level); })) {
        fail(fmt::format("phase '{}' t = {}: v = {} is not one of the configured levels [{}] of this phase", name, t, v,
                         fmt::join(levels, ", ")));
      }
    }

    const bool is_step = phase == Phase::kStepD || phase == Phase::kStepA;
    if (is_step && samples.size() < n + 1) {
      fail(
          fmt::format("phase '{}' has {} samples; at least n + 1 = {} are needed (the initial sample plus n samples "
                      "of response, the memory of the order-n subsystem)",
                      name, samples.size(), n + 1));
    }
    if (!is_step && samples.size() < pulse_minimum) {
      fail(
          fmt::format("phase '{}' has {} samples; at least 2*max(n,2)*(m+3) = {} are needed (two periods "
                      "T = max(n,2)(m+3) of the pulse sequence of Theorem 3.1, so the estimator sees every level)",
                      name, samples.size(), pulse_minimum));
    }
  }
}

std::vector<std::string> phase_length_notes(const ExperimentConfig& config, const Recording& recording,
                                            std::string_view data_name) {
  const auto step = config.step_length ? std::optional<std::int64_t>(std::int64_t{*config.step_length} + 1)
                                       : std::nullopt;
  const auto stated = [](const std::optional<int>& length) {
    return length ? std::optional<std::int64_t>(*length) : std::nullopt;
  };
  const std::array<std::pair<std::optional<std::int64_t>, const char*>, kPhaseCount> expected = {{
      {step, "step_length + 1"},
      {stated(config.pulse_length_d), "pulse_length_d"},
      {step, "step_length + 1"},
      {stated(config.pulse_length_a), "pulse_length_a"},
      {stated(config.val_length), "val_length"},
  }};
  std::vector<std::string> notes;
  for (const Phase phase : kAllPhases) {
    const auto& [length, key] = expected[phase_index(phase)];
    const auto samples = static_cast<std::int64_t>(recording.phase(phase).size());
    if (!length || samples == 0 || samples == *length) continue;
    notes.push_back(fmt::format("{}: phase '{}' has {} samples, the config's {} says {} ({})", data_name,
                                to_string(phase), samples, key, *length,
                                samples < *length ? "a run stopped early, or a file cut short?" : "more than the run"));
  }
  return notes;
}

Recording read_recording_for(const ExperimentConfig& config, const std::filesystem::path& path) {
  const Recording read = read_recording_csv(path);
  check_recording_matches(config, read, path.string());
  return snap_to_configured_levels(config, read);
}

}  // namespace lashid::sim
