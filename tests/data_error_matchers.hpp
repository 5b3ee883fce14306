// Test helpers for the data-format errors (DataError): what a failing action reported, and a readable assertion
// that a message contains a part (the file, the line, the key...).
#pragma once

#include <gtest/gtest.h>

#include <string>
#include <string_view>

#include "lashid/io/recording.hpp"

namespace lashid::test {

inline ::testing::AssertionResult Contains(std::string_view text, std::string_view part) {
  if (text.find(part) != std::string_view::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "\"" << text << "\" does not contain \"" << part << "\"";
}

/// Message of the DataError thrown by `action`, or a test failure if it throws none.
template <class Action>
std::string error_of(Action&& action) {
  try {
    action();
  } catch (const sim::DataError& error) {
    return error.what();
  }
  ADD_FAILURE() << "expected a DataError";
  return {};
}

}  // namespace lashid::test
