// JSON text to nlohmann::json, parsed in one file (json_text.cpp) for every test: nlohmann's parser is most of what
// a test that reads JSON costs to compile (about 6 s of each such file under ASan + UBSan, a few in Release), and ten
// test files read JSON.
#pragma once

#include <string_view>

#include <nlohmann/json.hpp>

/// nlohmann::json::parse(text): throws nlohmann::json::parse_error on text that is not JSON.
nlohmann::json parse_json(std::string_view text);
