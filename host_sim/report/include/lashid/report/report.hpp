// Text output shared by the subcommands.
#pragma once

#include <span>

#include "lashid/identify/identify.hpp"
#include "lashid/io/config.hpp"

namespace lashid::report {

/// ||x - ref|| / ||ref|| (Euclidean norms); x and ref have the same length.
double relative_difference(std::span<const double> x, std::span<const double> ref);

/// Estimates of one scheme, next to the truth when the config carries it.
void print_scheme_result(const sim::ExperimentConfig& config, const sim::SchemeResult& result);

}  // namespace lashid::report
