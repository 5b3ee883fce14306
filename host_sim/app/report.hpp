// Text output shared by the subcommands.
#pragma once

#include "lashid/sim/config.hpp"
#include "lashid/sim/identify.hpp"

namespace lashid::app {

/// Estimates of one scheme, next to the truth when the config carries it.
void print_scheme_result(const sim::ExperimentConfig& config, const sim::SchemeResult& result);

}  // namespace lashid::app
