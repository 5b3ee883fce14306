// JSON output of the input/output layer: the experiment config (the form parse_config_json reads) and an atomic
// writer for any JSON document. The one public header of the host libraries that exposes nlohmann::json: the
// result writers of report/ build on it.
#pragma once

#include <filesystem>

#include <nlohmann/json.hpp>

#include "lashid/io/config.hpp"

namespace lashid::sim {

// The JSON form read by parse_config_json (absent V_d / V_a / truth fields are omitted).
nlohmann::json to_json(const ExperimentConfig& config);

// Reads a JSON file as the config and plant readers do: a DataError naming the file (and the line where the parser
// knows it) for invalid JSON, a duplicate key, or nesting deeper than 64 levels.
nlohmann::json read_json_file(const std::filesystem::path& path);

// Writes `document` pretty-printed (indent 2) with a trailing newline, replacing `path` atomically.
void write_json_file(const std::filesystem::path& path, const nlohmann::json& document);

}  // namespace lashid::sim
