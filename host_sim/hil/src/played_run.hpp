// What the host plays and records in a firmware run (QEMU or in-process): the design, the plant, the recorder.
#pragma once

#include <optional>
#include <string_view>

#include "lashid/firmware/run_design.hpp"
#include "lashid/hil/any_plant.hpp"
#include "lashid/hil/hil.hpp"
#include "lashid/hil/run_recording.hpp"

namespace lashid::sim::detail {

/// options.design, or the design of options.scenario (run_design_of).
fw::RunDesign run_design_of(const HilOptions& options);

/// The plant file's plant (its operator starting at the design's v_min), or the scenario's. Throws DataError for a
/// malformed plant file or one whose borders do not cover the design's interval.
AnyPlant played_plant(const HilOptions& options, const fw::RunDesign& design);

/// Opens options.record (if set) before the run starts, so an unwritable path fails before QEMU does.
void start_recording(std::optional<RunRecorder>& recorder, const HilOptions& options, const fw::RunDesign& design);

/// Renames the recording onto its path (partial, with `how_it_ended`, if the run stopped early) and fills
/// result.recorded / recording_complete. Does nothing without a recorder.
void finish_recording(std::optional<RunRecorder>& recorder, std::string_view how_it_ended, HilResult& result);

}  // namespace lashid::sim::detail
