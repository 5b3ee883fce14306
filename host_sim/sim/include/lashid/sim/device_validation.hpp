// The validation input the device applies in a run of a design (phase `val`). The host uses the device's own
// generator so that a recording simulated from a config (`lashid simulate --plant`) and one recorded through the
// firmware (`lashid hil --record`) apply the same validation input.
#pragma once

#include <vector>

#include "lashid/firmware/run_design.hpp"

namespace lashid::sim {

/// design.val_length samples of fw::ValidationExcitation (seeded with design.val_seed), each the float the device
/// sends, widened to double. The design must have passed fw::check_design.
std::vector<double> device_validation_input(const fw::RunDesign& design);

}  // namespace lashid::sim
