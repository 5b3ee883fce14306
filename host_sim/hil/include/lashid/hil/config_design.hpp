// An experiment config (docs/data-format.md) as the design one firmware run executes (fw::RunDesign), in float32 as
// the device computes, and the firmware's verdict on it in the config's words. The one conversion for everything
// that gives a config to the firmware: `lashid design --check`, and `lashid hil` (to_run_design of hil.hpp, for a
// scenario's design, is built on it).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "lashid/firmware/run_design.hpp"
#include "lashid/io/config.hpp"

namespace lashid::sim {

/// The run-time design of `config` with `lengths`, as is: n, m, operator, interval and levels rounded to float32.
/// Throws DataError naming `source_name` and the key when the config cannot be expressed as a RunDesign at all:
/// 'V_d' or 'V_a' absent (a run executes the DIS and then the AIS), m beyond the image's level arrays
/// (fw::kMaxPoints), a number beyond float32's range, or a negative length. Whether the design obeys the rules is
/// fw::check_design()'s answer, not this function's: `lashid design --check` reports both.
fw::RunDesign run_design_as_is(const ExperimentConfig& config, const ExperimentLengths& lengths,
                               std::string_view source_name);

/// The design the firmware runs for a config file: its own lengths (experiment_lengths(config), the documented
/// defaults for absent keys), checked. Throws DataError naming `source_name` and the key, as run_design_as_is, or
/// with design_status_message() when fw::check_design() refuses it, e.g. "cfg.json: the firmware image cannot run
/// this design: in float32 'V_d[5]' = 1 is not greater than 'V_d[4]' = 1 (...)".
fw::RunDesign to_run_design(const ExperimentConfig& config, std::string_view source_name);

/// What fw::check_design()'s `status` means for `design`, naming the config key at fault, e.g. "'pulse_length_d' =
/// 20 is shorter than two pulse periods (2T = 36 for n = 2, m = 6)". Empty for kOk.
std::string design_status_message(fw::DesignStatus status, const fw::RunDesign& design);

/// Samples the firmware exchanges with the plant in a whole run of `design`, in order: the interval check of
/// Section 3.4 step 1 (backlash only: a v_M / v_m square wave of half-period 2T for four periods, 16T samples, as
/// fw::IdentificationSequencer runs it), the DIS step (L + 1) and DP pulse (N_d) experiments, the AIS step (L + 1)
/// and AP pulse (N_a) experiments, and the validation phase.
struct FirmwareRunSamples {
  std::uint64_t interval_check = 0;
  std::uint64_t steps = 0;   ///< both step experiments, 2 (L + 1)
  std::uint64_t pulses = 0;  ///< N_d + N_a
  std::uint64_t validation = 0;
  std::uint64_t total() const { return interval_check + steps + pulses + validation; }
};
FirmwareRunSamples firmware_run_samples(const fw::RunDesign& design);

}  // namespace lashid::sim
