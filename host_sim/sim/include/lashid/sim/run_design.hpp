// The design of one firmware run (fw::RunDesign: what the device executes) from an experiment config, and the
// validation input the device generates for it. The host uses the device's own generator so that a recording
// simulated from a config (`lashid simulate --plant`) and one recorded through the firmware (`lashid hil --record`)
// apply the same validation input.
#pragma once

#include <cstdint>
#include <vector>

#include "lashid/firmware/run_design.hpp"
#include "lashid/io/config.hpp"

namespace lashid::sim {

/// Lengths of a run's phases and the seed of its validation input.
struct RunLengths {
  int step_length = 2000;      ///< L of both step experiments: each has L + 1 samples
  int pulse_length_d = 2000;   ///< N of the DP experiment
  int pulse_length_a = 2000;   ///< N of the AP experiment
  int val_length = 2000;       ///< samples of the validation phase
  std::uint32_t val_seed = 1;  ///< seed of fw::ValidationExcitation
};

/// The lengths a config asks for. The one place that reads them from a config: until the config gains the keys
/// step_length, pulse_length_d, pulse_length_a, val_length and val_seed (issue 10, section 2), the defaults above
/// (those of sim::Scenario).
RunLengths run_lengths(const ExperimentConfig& config);

/// The device's design for `config` and `lengths` (levels and interval in float32, as the device holds them).
/// Throws std::invalid_argument when the device could not run it: V_d or V_a absent (a run always has both
/// schemes), m beyond the image's capacity, or any rule of fw::check_design (its message names the rule).
fw::RunDesign to_run_design(const ExperimentConfig& config, const RunLengths& lengths);

/// The `val` input the device applies for `design`: design.val_length samples of fw::ValidationExcitation, each
/// the float the device sends, widened to double.
std::vector<double> device_validation_input(const fw::RunDesign& design);

}  // namespace lashid::sim
