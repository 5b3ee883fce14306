// Test helpers for the data-format errors (DataError): what a failing action reported, and a readable assertion
// that a message contains a part (the file, the line, the key...).
#pragma once

#include <gtest/gtest.h>

#include <string>
#include <string_view>
#include <type_traits>

#include "lashid/io/recording.hpp"

namespace lashid::test {

inline ::testing::AssertionResult Contains(std::string_view text, std::string_view part) {
  if (text.find(part) != std::string_view::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "\"" << text << "\" does not contain \"" << part << "\"";
}

/// Message of the `Error` (a DataError unless named, e.g. error_of<std::invalid_argument>) thrown by `action`, or
/// a test failure if it throws none.
template <class Error = sim::DataError, class Action>
std::string error_of(Action&& action) {
  try {
    action();
  } catch (const Error& error) {
    return error.what();
  }
  ADD_FAILURE() << (std::is_same_v<Error, sim::DataError> ? "expected a DataError" : "expected the action to throw");
  return {};
}

}  // namespace lashid::test
