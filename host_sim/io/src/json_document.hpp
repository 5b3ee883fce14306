// Parsing a JSON file of the io layer (experiment config, plant file) with errors that name the file, the line of a
// syntax error and the key of a duplicate or unreadable value. Private to the io layer: the readers turn the document
// into typed structs and nothing else sees nlohmann's parser.
#pragma once

#include <string_view>

#include <nlohmann/json.hpp>

namespace lashid::sim::detail {

// Parses `text`; throws DataError naming `source_name`: "FILE:LINE: invalid JSON: ..." for a syntax error,
// "FILE: duplicate key 'a.b'" (nlohmann would silently keep the last one), "FILE: invalid JSON: ... (at key 'k')"
// for a value the parser refuses without a position (a number like 1e999).
nlohmann::json parse_json_document(std::string_view text, std::string_view source_name);

// nlohmann's message without its "[json.exception.parse_error.101] " prefix, which means nothing to a user.
std::string_view without_exception_id(std::string_view message);

}  // namespace lashid::sim::detail
