// What `lashid hil` checks a run's on-device estimates against (cmd_hil.cpp): the float32 identification of the
// run's own recording, with the samples the firmware set aside left out as it did, and the estimates of an earlier
// run's --json.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "lashid/firmware/messages.hpp"
#include "lashid/firmware/run_design.hpp"
#include "lashid/io/config.hpp"

namespace lashid::app {

/// `lashid identify --float` on the recording at `path`, one record per scheme in `device`, with the samples the
/// firmware set aside left out: those a streamed run named (run indices `set_aside`) and any y outside the design's
/// sensor range (the firmware's own float test). Throws DataError as `lashid identify` does.
std::vector<fw::EstimateRecord> identify_recording(const sim::ExperimentConfig& config, const std::string& path,
                                                   const std::vector<fw::EstimateRecord>& device,
                                                   const fw::RunDesign& design,
                                                   const std::vector<std::uint64_t>& set_aside);

/// The estimates of an earlier run's --json ("dis" and "ais": a, b, F, status). Throws DataError naming the file.
std::vector<fw::EstimateRecord> read_expected_estimates(const std::string& path);

}  // namespace lashid::app
