// Experiment configuration (JSON) and its consistency with a recording.
// The format is specified in docs/data-format.md.
#pragma once

#include <filesystem>
#include <optional>
#include <string_view>
#include <vector>

#include "lashid/io/recording.hpp"

namespace lashid::sim {

// The range of model sizes the estimator is compiled for. Change them here; config validation and
// everything else on the host side follows.
inline constexpr int kMinOrder = 1;  // n: order of the linear subsystem A(q^-1), B(q^-1)
inline constexpr int kMaxOrder = 3;
inline constexpr int kMinPoints = 1;  // m: number of border points per scheme (V_d / V_a)
inline constexpr int kMaxPoints = 8;

enum class OperatorKind { kSwitch, kBacklash };
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
  friend bool operator==(const ExperimentConfig&, const ExperimentConfig&) = default;
};

// Reads and validates a config file. Throws DataError naming the file and the offending key.
ExperimentConfig read_config_json(const std::filesystem::path& path);
// Same as read_config_json, from text in memory; `source_name` stands for the file name in errors.
ExperimentConfig parse_config_json(std::string_view text, std::string_view source_name);

// Checks that `recording` can be used with `config`: the schemes of the recorded phases are
// configured, identification inputs lie in [v_min, v_max] and take only the configured levels, and
// step and pulse phases are long enough. Throws DataError naming `data_name`, the phase and t.
void check_recording_matches(const ExperimentConfig& config, const Recording& recording, std::string_view data_name);

}  // namespace lashid::sim
