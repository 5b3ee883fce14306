// Checks of command-line values that CLI11's own validators do not make (main.cpp).
#pragma once

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <string>
#include <system_error>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

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

}  // namespace lashid::app
