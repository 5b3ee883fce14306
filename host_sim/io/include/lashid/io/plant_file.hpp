// Plant file (JSON): the actuator and plant `lashid simulate --plant` and `lashid hil --plant` play, described by
// numbers instead of C++. The format is specified in docs/data-format.md ("Plant file").
//
//   {"operator": "switch" | "backlash",
//    "borders": {"v": [...], "ascending": [...], "descending": [...]},   one grid, linear between its points
//    "a": [a1, ..., an], "b": [b1, ..., bn],       A = 1 + a1 q^-1 + ..., B = b1 q^-1 + ...
//    "equation_noise_std": s,                      white xi(t) in A y = B u + xi
//    "sensor_noise": {"std": s, "pole": c},        optional: AR(1) noise added to y, stationary std s
//    "input_lag": lambda, "dead_time": d, "sensor_drift_per_sample": delta}   optional hidden effects
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "lashid/io/config.hpp"

namespace lashid::sim {

/// Coloured measurement noise e(t) = pole e(t-1) + w(t) added to y, with the stationary standard deviation `std`.
struct SensorNoiseSpec {
  double std = 0;   ///< >= 0
  double pole = 0;  ///< in (-1, 1)
  friend bool operator==(const SensorNoiseSpec&, const SensorNoiseSpec&) = default;
};

/// Largest `dead_time` a plant file may ask for, in samples: the delay line is allocated at once, so an absurd
/// value must be an error, not an out-of-memory crash.
inline constexpr int kMaxDeadTime = 10000;

/// A validated plant file. Defaults are the values of the optional keys when absent.
struct PlantSpec {
  OperatorKind op = OperatorKind::kSwitch;
  std::vector<double> border_v;           ///< >= 2 abscissas, strictly increasing
  std::vector<double> border_ascending;   ///< C_a at border_v (same size)
  std::vector<double> border_descending;  ///< C_d at border_v (same size)
  std::vector<double> a;                  ///< n >= 1 coefficients; A(q^-1) is stable
  std::vector<double> b;                  ///< n coefficients
  double equation_noise_std = 0;          ///< >= 0
  std::optional<SensorNoiseSpec> sensor_noise;
  double input_lag = 0;                   ///< lambda in [0, 1)
  int dead_time = 0;                      ///< samples in [0, kMaxDeadTime]
  double sensor_drift_per_sample = 0;     ///< finite
  /// Keys the format does not define, with their path ("name", "borders.note"): allowed and ignored, and listed
  /// here so the commands can mention them (a misspelt optional key would otherwise vanish silently).
  std::vector<std::string> ignored_keys;
  friend bool operator==(const PlantSpec&, const PlantSpec&) = default;
};

/// Reads and validates a plant file. Throws DataError naming the file and the offending key.
PlantSpec read_plant_json(const std::filesystem::path& path);
/// Same as read_plant_json, from text in memory; `source_name` stands for the file name in errors.
PlantSpec parse_plant_json(std::string_view text, std::string_view source_name);

/// Throws DataError naming `plant_name` and 'borders.v' unless the borders' grid covers [v_min, v_max]: outside its
/// grid a border would be extended by its end value, which is never what a plant file meant.
void check_plant_covers(const PlantSpec& plant, double v_min, double v_max, std::string_view plant_name);

}  // namespace lashid::sim
