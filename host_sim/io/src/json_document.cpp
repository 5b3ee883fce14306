// The JSON parse shared by the config and plant-file readers: duplicate keys and unreadable values named.
#include "json_document.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "lashid/io/data_error.hpp"

namespace lashid::sim::detail {

namespace {

using nlohmann::json;

// Where the parser is, as far as keys go: the open objects and the last key seen. Used to report
// duplicate keys, and to name the key whose value the parser rejected (e.g. a number overflow).
struct JsonKeyTracker {
  struct OpenObject {
    std::string path;
    std::set<std::string> keys;
  };
  std::vector<OpenObject> objects;
  std::string last_key_path;
};

// nlohmann keeps the last of duplicate keys silently; a repeated key is as likely a mistake as a
// typo, so the parse callback reports it. It also stops a document nested deeper than kMaxJsonDepth as soon as the
// parser gets there: the project's files are a few levels deep, while 100,000 nested arrays crashed the reader
// (recursion in what handles the value afterwards) and 50,000 nested objects took 2.5 GB.
json::parser_callback_t duplicate_key_detector(JsonKeyTracker& tracker, std::string_view source_name) {
  return [&tracker, source_name](int depth, json::parse_event_t event, json& parsed) {
    if ((event == json::parse_event_t::object_start || event == json::parse_event_t::array_start) &&
        depth >= kMaxJsonDepth) {
      throw DataError(source_name, fmt::format("JSON nested deeper than {} levels of objects and arrays; the "
                                               "project's files need a few",
                                               kMaxJsonDepth));
    }
    switch (event) {
      case json::parse_event_t::object_start:
        tracker.objects.push_back({tracker.objects.empty() ? std::string() : tracker.last_key_path, {}});
        break;
      case json::parse_event_t::object_end:
        tracker.objects.pop_back();
        break;
      case json::parse_event_t::key: {
        JsonKeyTracker::OpenObject& object = tracker.objects.back();
        const auto& key = parsed.get_ref<const std::string&>();
        tracker.last_key_path = object.path.empty() ? key : fmt::format("{}.{}", object.path, key);
        if (!object.keys.insert(key).second) {
          throw DataError(source_name, fmt::format("duplicate key '{}'", tracker.last_key_path));
        }
        break;
      }
      default:
        break;
    }
    return true;
  };
}

std::size_t line_of_byte(std::string_view text, std::size_t byte_position) {
  const std::string_view before = text.substr(0, std::min(byte_position, text.size()));
  return 1 + static_cast<std::size_t>(std::count(before.begin(), before.end(), '\n'));
}

}  // namespace

std::string shown(const nlohmann::json& value) {
  constexpr std::size_t kLongest = 60;
  std::string text = value.dump(-1, ' ', false, json::error_handler_t::replace);
  if (text.size() > kLongest) text = text.substr(0, kLongest - 3) + "...";
  return text;
}

std::string_view without_exception_id(std::string_view message) {
  if (message.starts_with("[json.exception.")) {
    if (const std::size_t end = message.find("] "); end != std::string_view::npos) message.remove_prefix(end + 2);
  }
  return message;
}

json parse_json_document(std::string_view text, std::string_view source_name) {
  JsonKeyTracker tracker;
  try {
    return json::parse(text, duplicate_key_detector(tracker, source_name));
  } catch (const json::parse_error& error) {
    throw DataError(source_name, line_of_byte(text, error.byte),
                    fmt::format("invalid JSON: {}", without_exception_id(error.what())));
  } catch (const json::exception& error) {  // e.g. out_of_range for a number like 1e999, which has no position
    const std::string where =
        tracker.last_key_path.empty() ? std::string() : fmt::format(" (at key '{}')", tracker.last_key_path);
    throw DataError(source_name, fmt::format("invalid JSON: {}{}", without_exception_id(error.what()), where));
  }
}

void JsonFieldReader::fail(std::string_view message) const { throw DataError(source_name_, message); }

double JsonFieldReader::read_finite(const nlohmann::json& value, std::string_view key) const {
  if (!value.is_number()) fail(fmt::format("'{}' must be a number, got {}", key, shown(value)));
  const auto number = value.get<double>();
  if (!std::isfinite(number)) fail(fmt::format("'{}' must be a finite number", key));
  return number;
}

std::vector<double> JsonFieldReader::read_numbers(const nlohmann::json& value, std::string_view key) const {
  if (!value.is_array()) fail(fmt::format("'{}' must be an array of numbers, got {}", key, value.type_name()));
  std::vector<double> numbers;
  numbers.reserve(value.size());
  for (std::size_t i = 0; i < value.size(); ++i) {
    numbers.push_back(read_finite(value.at(i), fmt::format("{}[{}]", key, i)));
  }
  return numbers;
}

OperatorKind JsonFieldReader::read_operator(const nlohmann::json& value) const {
  if (value == "switch") return OperatorKind::kSwitch;
  if (value == "backlash") return OperatorKind::kBacklash;
  fail(fmt::format("'operator' must be \"switch\" or \"backlash\", got {}", shown(value)));
}

}  // namespace lashid::sim::detail
