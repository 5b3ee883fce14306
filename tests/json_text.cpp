#include "json_text.hpp"

nlohmann::json parse_json(std::string_view text) { return nlohmann::json::parse(text); }
