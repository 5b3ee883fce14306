// Checks of command-line values that CLI11's own validators do not make, and the words it did not know (main.cpp).
#pragma once

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <fmt/ranges.h>

namespace lashid::app {

// A seed is a decimal integer from 0 to 2^64 - 1. CLI11 converts "-1" to an unsigned seed by wrapping it around to
// 2^64 - 1, and clamps a larger number to 2^64 - 1 without a word: both are refused here instead.
inline const CLI::Validator kNonNegativeSeed(
    [](const std::string& value) {
      if (value.starts_with('-')) return std::string("must not be negative");
      std::uint64_t seed = 0;
      const auto [end, error] = std::from_chars(value.data(), value.data() + value.size(), seed);
      if (error == std::errc::result_out_of_range) {
        return fmt::format("must be at most {} (2^64 - 1)", std::numeric_limits<std::uint64_t>::max());
      }
      // Not a number at all: CLI11's own conversion names the error.
      return std::string();
    },
    "NONNEGATIVE");

// A 64-bit integer option whose value lies beyond int64: CLI11 clamps it to the type's end without a word, and the
// option's own check then quoted the clamped number (`--step-length 18446744073709551615` was said as
// 9223372036854775807). Refused here quoting the value as typed; `max` is the option's own largest value.
inline CLI::Validator int64_as_typed(std::int64_t max) {
  return CLI::Validator(
      [max](const std::string& value) {
        std::int64_t number = 0;
        const auto [end, error] = std::from_chars(value.data(), value.data() + value.size(), number);
        if (error != std::errc::result_out_of_range) return std::string();  // in range, or CLI11's own error
        return value.starts_with('-') ? fmt::format("{} must not be negative", value)
                                      : fmt::format("{} is too large (at most {})", value, max);
      },
      "INT64");
}

// CLI11's number checks (Range, NonNegativeNumber, ...) compare, and every comparison with NaN is false: "nan"
// passed them and reached the code as a value. Every floating-point option therefore also gets this check.
inline const CLI::Validator kFinite(
    [](const std::string& value) {
      char* end = nullptr;
      const double x = std::strtod(value.c_str(), &end);
      // Not a number at all: CLI11's own conversion names the error.
      if (end == value.c_str()) return std::string();
      return std::isfinite(x) ? std::string() : std::string("must be a finite number");
    },
    "FINITE");

// The closest of `names` to `word` by edit distance, if within 2 edits ("idntify" -> "identify").
inline std::optional<std::string> closest_name(const std::string& word, const std::vector<std::string>& names) {
  std::optional<std::string> best;
  std::size_t best_distance = 3;
  for (const std::string& name : names) {
    std::vector<std::size_t> row(name.size() + 1);
    for (std::size_t j = 0; j <= name.size(); ++j) row[j] = j;
    for (std::size_t i = 1; i <= word.size(); ++i) {
      std::size_t diagonal = row[0];
      row[0] = i;
      for (std::size_t j = 1; j <= name.size(); ++j) {
        const std::size_t up = row[j];
        row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (word[i - 1] == name[j - 1] ? 0U : 1U)});
        diagonal = up;
      }
    }
    if (row[name.size()] < best_distance) {
      best_distance = row[name.size()];
      best = name;
    }
  }
  return best;
}

// CLI11 reports a missing required option or subcommand before the words it did not know, so a misspelt command or
// option was said as "A subcommand is required" or "--config is required". The word the user mistyped is the
// error: named here, with the closest known name. Empty when every word is known.
inline std::optional<std::string> unknown_word(const CLI::App& app, int argc, const char* const* argv) {
  const CLI::App* command = nullptr;
  std::vector<std::string> commands;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
    commands.push_back(sub->get_name());
    if (sub->parsed()) command = sub;
  }
  if (command == nullptr) {
    if (argc < 2 || std::string_view(argv[1]).starts_with('-')) return std::nullopt;
    const std::optional<std::string> near = closest_name(argv[1], commands);
    return fmt::format("'{}' is not a command{}; the commands: {}", argv[1],
                       near ? fmt::format(" (did you mean '{}'?)", *near) : std::string(), fmt::join(commands, ", "));
  }
  std::vector<std::string> options;
  for (const CLI::Option* o : command->get_options()) {
    for (const std::string& name : o->get_lnames()) options.push_back("--" + name);
  }
  for (int i = 2; i < argc; ++i) {
    const std::string word(argv[i]);
    if (!word.starts_with("--")) continue;
    const std::string name = word.substr(0, word.find('='));
    if (std::find(options.begin(), options.end(), name) != options.end()) continue;
    const std::optional<std::string> near = closest_name(name, options);
    return fmt::format("{}: unknown option {}{}", command->get_name(), name,
                       near ? fmt::format(" (did you mean {}?)", *near) : std::string());
  }
  return std::nullopt;
}

}  // namespace lashid::app
