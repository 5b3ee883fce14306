// Text output shared by the subcommands.
#pragma once

#include <string>
#include <vector>

#include "lashid/identify/identify.hpp"
#include "lashid/io/config.hpp"

namespace lashid::report {

/// Estimates of one scheme, next to the truth when the config carries it.
/// With a warning line when the border is not identified (border_check.hpp).
void print_scheme_result(const sim::ExperimentConfig& config, const sim::SchemeResult& result);

/// The labels "F(V_j)" of the levels, each with as few significant digits as tell all of them apart (6 at least,
/// as {:g}; up to the shortest round-trip form): on an interval such as [1e6, 1e6 + 1] six digits printed every
/// level as F(1e+06).
std::vector<std::string> level_labels(const std::vector<double>& levels);

}  // namespace lashid::report
