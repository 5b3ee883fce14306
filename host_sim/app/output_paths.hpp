// No command writes over one of its own files (issue 14, "no lost data").
#pragma once

#include <CLI/CLI.hpp>

namespace lashid::app {

/// The options through which a command writes files.
inline constexpr const char* kOutputOptions[] = {"--out", "--json", "--config-out", "--plot", "--record"};

/// Throws std::invalid_argument, naming both options, when an output option of the parsed `command` names the same
/// file as another of its options (an input such as --data or --config, or another output): `identify --json REC.csv
/// --data REC.csv` would replace the recording with JSON. The same file means the same path after resolving symbolic
/// links and `..`, or the same inode when both exist (a hard link).
void refuse_overwriting_own_files(const CLI::App& command);

}  // namespace lashid::app
