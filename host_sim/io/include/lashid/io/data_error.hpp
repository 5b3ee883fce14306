// The one error type of the input/output layer: what was wrong, and in which file (and line).
#pragma once

#include <cstddef>
#include <optional>
#include <stdexcept>
#include <string_view>

namespace lashid::sim {

// Invalid or unreadable data. what() is "FILE:LINE: message", or "FILE: message" when no single
// line is to blame, so editors and terminals can jump to the spot.
class DataError : public std::runtime_error {
 public:
  DataError(std::string_view source, std::string_view message);
  DataError(std::string_view source, std::size_t line, std::string_view message);

  // 1-based line number, if the error was tied to one line.
  std::optional<std::size_t> line() const noexcept { return line_; }

 private:
  std::optional<std::size_t> line_;
};

}  // namespace lashid::sim
