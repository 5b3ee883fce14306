// Text output shared by the subcommands.
#pragma once

#include "lashid/identify/identify.hpp"
#include "lashid/io/config.hpp"

namespace lashid::report {

/// Estimates of one scheme, next to the truth when the config carries it.
void print_scheme_result(const sim::ExperimentConfig& config, const sim::SchemeResult& result);

}  // namespace lashid::report
