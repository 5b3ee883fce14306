// Parsing a JSON file of the io layer (experiment config, plant file) with errors that name the file, the line of a
// syntax error and the key of a duplicate or unreadable value. Private to the io layer: the readers turn the document
// into typed structs and nothing else sees nlohmann's parser.
#pragma once

#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "lashid/io/config.hpp"

namespace lashid::sim::detail {

// Parses `text`; throws DataError naming `source_name`: "FILE:LINE: invalid JSON: ..." for a syntax error,
// "FILE: duplicate key 'a.b'" (nlohmann would silently keep the last one), "FILE: invalid JSON: ... (at key 'k')"
// for a value the parser refuses without a position (a number like 1e999).
nlohmann::json parse_json_document(std::string_view text, std::string_view source_name);

/// Deeper nesting of objects and arrays is refused while parsing (DataError), before it costs memory or stack.
inline constexpr int kMaxJsonDepth = 64;

// A value as an error message quotes it: its JSON text, cut to 60 characters ("...") so that a large value (an
// array of a million numbers where one was expected) does not flood the terminal.
std::string shown(const nlohmann::json& value);

// nlohmann's message without its "[json.exception.parse_error.101] " prefix, which means nothing to a user.
std::string_view without_exception_id(std::string_view message);

// What the config and plant-file readers share: errors that name the file and the key, and the typed reads of one
// value. Each reader adds its own keys, rules and idea of a required key (null is absent in a plant file only).
class JsonFieldReader {
 public:
  explicit JsonFieldReader(std::string_view source_name) : source_name_(source_name) {}

 protected:
  // Throws DataError "FILE: message".
  [[noreturn]] void fail(std::string_view message) const;
  // A finite number: "'key' must be a number, got ...", "'key' must be a finite number".
  double read_finite(const nlohmann::json& value, std::string_view key) const;
  // An array of finite numbers, each named 'key[i]' in errors.
  std::vector<double> read_numbers(const nlohmann::json& value, std::string_view key) const;
  // "switch" or "backlash".
  OperatorKind read_operator(const nlohmann::json& value) const;

  std::string_view source_name_;
};

}  // namespace lashid::sim::detail
