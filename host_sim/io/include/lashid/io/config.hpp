// Experiment configuration (JSON) and its consistency with a recording.
// The format is specified in docs/data-format.md.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "lashid/io/recording.hpp"

namespace lashid::sim {

// The range of model sizes the host estimator runs: the capacity it is compiled for, with n and m chosen at run
// time, the same as the firmware image's (a static_assert in hil/ keeps them equal), so that every recording of a
// design the image runs can be identified and diagnosed on the host. Config validation follows them.
inline constexpr int kMinOrder = 1;  // n: order of the linear subsystem A(q^-1), B(q^-1)
inline constexpr int kMaxOrder = 4;
inline constexpr int kMinPoints = 1;  // m: number of border points per scheme (V_d / V_a)
inline constexpr int kMaxPoints = 10;

// Defaults of the optional experiment lengths (docs/data-format.md), applied by experiment_lengths(). L and the
// validation length are the paper's example lengths; N is rounded up to whole pulse periods (default_pulse_length).
inline constexpr int kDefaultStepLength = 2000;
inline constexpr int kDefaultPulseSamples = 2000;  // the default N is the first whole number of periods >= this
inline constexpr int kDefaultValLength = 1000;
inline constexpr std::uint32_t kDefaultValSeed = 1;

enum class OperatorKind { kSwitch, kBacklash };
/// The other operator type (a switch for a backlash and the reverse).
constexpr OperatorKind other_operator(OperatorKind kind) {
  return kind == OperatorKind::kSwitch ? OperatorKind::kBacklash : OperatorKind::kSwitch;
}
/// "switch" or "backlash", as in the config file.
std::string_view to_string(OperatorKind kind);

// The true system, when known (written by the simulator). Empty vectors / nullopt = unknown.
struct Truth {
  std::vector<double> a;          // a_1..a_n of A(q^-1) = 1 + a_1 q^-1 + ... + a_n q^-n
  std::vector<double> b;          // b_1..b_n of B(q^-1) = b_1 q^-1 + ... + b_n q^-n
  std::vector<double> F_d;        // F^d(V_j^d), j = 1..m (paper eq. 3.2)
  std::vector<double> F_a;        // F^a(V_j^a), j = 1..m
  std::optional<double> ybar0_d;  // mean output of the descendent step experiment
  std::optional<double> ybar0_a;  // mean output of the ascendent step experiment
  friend bool operator==(const Truth&, const Truth&) = default;
};

struct ExperimentConfig {
  int n;                    // order of the linear subsystem
  int m;                    // points per border
  double v_min;             // v_m of the paper
  double v_max;             // v_M of the paper
  std::vector<double> V_d;  // v_min = V_d[0] < ... < V_d[m-1] < v_max; empty when DIS is not used
  std::vector<double> V_a;  // v_max = V_a[0] > ... > V_a[m-1] > v_min; empty when AIS is not used
  OperatorKind op;
  std::optional<Truth> truth;
  // The experiments a run executes. nullopt: the key is absent from the file, experiment_lengths() supplies the
  // default. Kept apart from the defaults so that a file is written back with exactly the keys it had.
  std::optional<int> step_length;            // L: each step experiment (3.4)/(4.1) has L + 1 samples, t = 0..L
  std::optional<int> pulse_length_d;         // N of the DP experiment (3.1)
  std::optional<int> pulse_length_a;         // N of the AP experiment (4.2)
  std::optional<int> val_length;             // samples of the validation phase (0: none)
  std::optional<std::uint32_t> val_seed;     // seed of the validation excitation
  // The sensor's range [lo, hi] (key "sensor_range"): a value the device measures outside it is a bad sensor value,
  // counted and never estimated from. nullopt: unlimited (only NaN and infinite values are bad).
  std::optional<std::array<double, 2>> sensor_range;
  friend bool operator==(const ExperimentConfig&, const ExperimentConfig&) = default;
};

// The lengths and seed a run of a config uses, every one resolved.
struct ExperimentLengths {
  int step_length;
  int pulse_length_d;
  int pulse_length_a;
  int val_length;
  std::uint32_t val_seed;
  friend bool operator==(const ExperimentLengths&, const ExperimentLengths&) = default;
};

/// The one place the defaults are applied: each key of `config` that is given, otherwise its documented default
/// (L = 2000, N = default_pulse_length(n, m) for both pulse experiments, 1000 validation samples, seed 1).
ExperimentLengths experiment_lengths(const ExperimentConfig& config);

/// Default N of a pulse experiment: the smallest whole number of pulse periods T = max(n,2)(m+3)
/// (est::schedule::period) that is at least 2000 samples and at least two periods; whole periods, so that every
/// level is pulsed equally often.
int default_pulse_length(int n, int m);

/// The range of n and m a reader accepts, and the words its error uses for that range. The default is the host
/// estimator's compiled range; `lashid design --check` widens it to the firmware image's capacity so that it can say
/// which side refuses a design.
struct ConfigLimits {
  int max_order = kMaxOrder;
  int max_points = kMaxPoints;
  std::string_view range_name = "the compiled range";
};

// Reads and validates a config file. Throws DataError naming the file and the offending key.
ExperimentConfig read_config_json(const std::filesystem::path& path, const ConfigLimits& limits = {});
// Same as read_config_json, from text in memory; `source_name` stands for the file name in errors.
ExperimentConfig parse_config_json(std::string_view text, std::string_view source_name,
                                   const ConfigLimits& limits = {});

// Checks that `recording` can be used with `config`: the schemes of the recorded phases are
// configured, identification inputs lie in [v_min, v_max] and take only the configured levels, and
// step and pulse phases are long enough. Throws DataError naming `data_name`, the phase and t.
void check_recording_matches(const ExperimentConfig& config, const Recording& recording, std::string_view data_name);

// How far a recorded input of an identification phase may lie from a configured level and still be that level:
// the larger of 64 float32 eps of the interval's width (the firmware classifier's resolution) and half a float32 eps
// of max(|v_min|, |v_max|). A recording made by a float32 device (the firmware through `lashid hil --record`) holds
// float(V_j), which differs from a level such as 1/3 by up to half a float32 ulp.
double level_tolerance(const ExperimentConfig& config);

// The config's sensor range as a float32 device applies it (fw::RunDesign::sensor_min/max): each bound in float32,
// then one float32 step outwards, so that a value the double range allows is never a bad value on the device.
// [-inf, inf] without a range; a bound beyond float32's range is infinite (to_run_design refuses it by name).
std::array<float, 2> float32_sensor_range(const ExperimentConfig& config);

// The recording with every input of an identification phase that lies within level_tolerance() of one of the
// phase's configured levels replaced by the nearest such level (validation inputs untouched): what the double
// estimator, whose own matching is to 64 double eps, must be given. Call after check_recording_matches.
Recording snap_to_configured_levels(const ExperimentConfig& config, const Recording& recording);

// A recording as `identify`, `diagnose` and `hil` use it with `config`: read_recording_csv, check_recording_matches,
// then snap_to_configured_levels (a float32 device's float(V_j) given back as the configured V_j). Throws DataError
// naming `path`.
Recording read_recording_for(const ExperimentConfig& config, const std::filesystem::path& path);

// One line per recorded phase whose sample count differs from the length the config states for it (only the keys
// the config sets: step_length (+ 1 per step phase), pulse_length_d/_a, val_length): a run stopped early, or a file
// cut short. Not an error: a recording holds what was measured (docs/data-format.md); the tools print these as notes.
std::vector<std::string> phase_length_notes(const ExperimentConfig& config, const Recording& recording,
                                            std::string_view data_name);

}  // namespace lashid::sim
