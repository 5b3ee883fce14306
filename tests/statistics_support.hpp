// Shared by the statistics tests: relative tolerance and special values.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace lashid::sim::stats::test {

inline constexpr double nan = std::numeric_limits<double>::quiet_NaN();
inline constexpr double inf = std::numeric_limits<double>::infinity();

// |actual - expected| <= tolerance * |expected|.
inline ::testing::AssertionResult relatively_near(double actual, double expected, double tolerance) {
  if (std::fabs(actual - expected) <= tolerance * std::fabs(expected)) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "actual " << actual << " vs expected " << expected << " (relative error "
                                       << std::fabs(actual - expected) / std::fabs(expected) << " > " << tolerance
                                       << ")";
}

}  // namespace lashid::sim::stats::test
