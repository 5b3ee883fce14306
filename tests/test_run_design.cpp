// The run-time design of a firmware run: the paper's rules at run time (one named status each), its wire format,
// and the validation excitation generated on the device.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "lashid/firmware/paper_run_designs.hpp"
#include "lashid/firmware/run_design.hpp"
#include "lashid/firmware/validation_excitation.hpp"

namespace {

using namespace lashid;
using fw::DesignStatus;

// n = 3, m = 4 on [-1, 1]: T = 3 (4 + 3) = 21 by (3.25), so two periods are 42 samples.
fw::RunDesign valid_design() {
  fw::RunDesign d;
  d.op = fw::OperatorKind::kBacklash;
  d.n = 3;
  d.m = 4;
  d.v_min = -1.0f;
  d.v_max = 1.0f;
  d.V_d = {-1.0f, -0.5f, 0.0f, 0.5f};
  d.V_a = {1.0f, 0.5f, 0.0f, -0.5f};
  d.step_length = 4;
  d.pulse_length_d = 42;
  d.pulse_length_a = 42;
  d.val_length = 100;
  d.val_seed = 3;
  return d;
}

TEST(CheckDesign, AcceptsTheBoundaryOfEveryRule) {
  EXPECT_EQ(valid_design().period(), 21);
  EXPECT_EQ(fw::check_design(valid_design()), DesignStatus::kOk);
  EXPECT_EQ(fw::check_design(fw::kDisPaperRun), DesignStatus::kOk);
  EXPECT_EQ(fw::check_design(fw::kAisPaperRun), DesignStatus::kOk);
  fw::RunDesign d = valid_design();
  d.n = 4;
  d.m = 10;  // the capacity: T = 4 (10 + 3) = 52
  for (std::size_t j = 0; j < 10; ++j) {
    d.V_d[j] = -1.0f + 0.15f * static_cast<float>(j);
    d.V_a[j] = 1.0f - 0.15f * static_cast<float>(j);
  }
  d.pulse_length_d = d.pulse_length_a = 104;
  d.step_length = 5;  // L > n = 4
  EXPECT_EQ(fw::check_design(d), DesignStatus::kOk);
}

TEST(CheckDesign, NamesEachViolatedRule) {
  const auto with = [](auto change) {
    fw::RunDesign d = valid_design();
    change(d);
    return fw::check_design(d);
  };
  EXPECT_EQ(with([](auto& d) { d.op = static_cast<fw::OperatorKind>(7); }), DesignStatus::kUnknownOperator);
  EXPECT_EQ(with([](auto& d) { d.n = 0; }), DesignStatus::kOrderOutOfRange);
  EXPECT_EQ(with([](auto& d) { d.n = 5; }), DesignStatus::kOrderOutOfRange);
  EXPECT_EQ(with([](auto& d) { d.m = 0; }), DesignStatus::kPointsOutOfRange);
  EXPECT_EQ(with([](auto& d) { d.m = 11; }), DesignStatus::kPointsOutOfRange);
  EXPECT_EQ(with([](auto& d) { d.v_max = d.v_min; }), DesignStatus::kIntervalInvalid);
  EXPECT_EQ(with([](auto& d) { d.v_min = std::numeric_limits<float>::infinity(); }), DesignStatus::kIntervalInvalid);
  EXPECT_EQ(with([](auto& d) { d.V_a[2] = std::numeric_limits<float>::quiet_NaN(); }),
            DesignStatus::kLevelNotFinite);
  EXPECT_EQ(with([](auto& d) { d.V_d[0] = -0.9f; }), DesignStatus::kVdFirstNotVMin);
  EXPECT_EQ(with([](auto& d) { d.V_d[2] = -0.5f; }), DesignStatus::kVdNotIncreasing);
  EXPECT_EQ(with([](auto& d) { d.V_d[3] = 1.0f; }), DesignStatus::kVdNotBelowVMax);
  EXPECT_EQ(with([](auto& d) { d.V_a[0] = 0.9f; }), DesignStatus::kVaFirstNotVMax);
  EXPECT_EQ(with([](auto& d) { d.V_a[3] = 0.0f; }), DesignStatus::kVaNotDecreasing);
  EXPECT_EQ(with([](auto& d) { d.V_a[3] = -1.0f; }), DesignStatus::kVaNotAboveVMin);
  // Strictly ordered, but 1e-7 apart: below float32's resolution of the levels (64 eps ~ 7.6e-6 of the step 2).
  EXPECT_EQ(with([](auto& d) { d.V_d[3] = std::nextafter(1.0f, 0.0f); }), DesignStatus::kLevelsTooClose);
  EXPECT_EQ(with([](auto& d) { d.step_length = 3; }), DesignStatus::kStepTooShort);  // L must exceed n = 3
  EXPECT_EQ(with([](auto& d) { d.pulse_length_d = 41; }), DesignStatus::kPulseDTooShort);
  EXPECT_EQ(with([](auto& d) { d.pulse_length_a = 41; }), DesignStatus::kPulseATooShort);
  EXPECT_EQ(with([](auto& d) { d.val_length = 0xFFFF'FFF0U; }), DesignStatus::kRunTooLong);
  // 2^28 pulse samples are the most the float32 estimator is held to; one more is refused, for either scheme.
  EXPECT_EQ(with([](auto& d) { d.pulse_length_d = 1U << 28; }), DesignStatus::kOk);
  EXPECT_EQ(with([](auto& d) { d.pulse_length_d = (1U << 28) + 1; }), DesignStatus::kPulseTooLong);
  EXPECT_EQ(with([](auto& d) { d.pulse_length_a = (1U << 28) + 1; }), DesignStatus::kPulseTooLong);
  // Every status has its own words.
  std::set<std::string> names;
  for (int s = 0; s <= static_cast<int>(DesignStatus::kOutsideActuatorRange); ++s) {
    names.insert(fw::to_string(static_cast<DesignStatus>(s)));
  }
  EXPECT_EQ(names.size(), static_cast<std::size_t>(DesignStatus::kOutsideActuatorRange) + 1);
}

TEST(RunDesignWire, RoundTripsAndRefusesMalformedPayloads) {
  const fw::RunDesign d = valid_design();
  hal::link::PayloadWriter w;
  d.encode(w);
  ASSERT_TRUE(w.ok());
  // op, n, m + v_min, v_max + 5 lengths + sensor_min, sensor_max + 2 x 4 levels: 3 + 8 + 20 + 8 + 32.
  EXPECT_EQ(w.size(), 71u);
  EXPECT_EQ(fw::RunDesign::encoded_size(10), 3u + 8 + 20 + 8 + 80);
  fw::RunDesign back;
  ASSERT_EQ(back.decode(hal::link::PayloadReader(w.data(), w.size())), DesignStatus::kOk);
  EXPECT_EQ(back.n, 3);
  EXPECT_EQ(back.V_a[3], -0.5f);
  EXPECT_EQ(back.val_seed, 3u);
  EXPECT_EQ(back.op, fw::OperatorKind::kBacklash);
  // One byte short, one byte long, m beyond the capacity, an unknown operator byte.
  EXPECT_EQ(back.decode(hal::link::PayloadReader(w.data(), w.size() - 1)), DesignStatus::kMalformed);
  std::vector<std::uint8_t> bytes(w.data(), w.data() + w.size());
  bytes.push_back(0);
  EXPECT_EQ(back.decode(hal::link::PayloadReader(bytes.data(), bytes.size())), DesignStatus::kMalformed);
  bytes.pop_back();
  bytes[2] = 11;
  EXPECT_EQ(back.decode(hal::link::PayloadReader(bytes.data(), bytes.size())), DesignStatus::kPointsOutOfRange);
  bytes[2] = 4;
  bytes[0] = 2;
  EXPECT_EQ(back.decode(hal::link::PayloadReader(bytes.data(), bytes.size())), DesignStatus::kUnknownOperator);
}

TEST(ValidationExcitation, VisitsTheLevelsWithStepsFromTheExtremesAndSmallReversals) {
  const fw::RunDesign d = valid_design();
  fw::ValidationExcitation gen(d);
  // {v_min, v_max} U V_d U V_a merged: -1, -0.5, 0, 0.5, 1.
  ASSERT_EQ(gen.level_count(), 5);
  EXPECT_EQ(gen.level(0), -1.0f);
  EXPECT_EQ(gen.level(4), 1.0f);
  std::vector<float> v(20000);
  for (float& x : v) x = gen.next();
  // Holds: the runs of equal values last kMinHold..kMaxHold samples (two equal holds in a row can merge).
  std::vector<std::pair<float, int>> runs;
  for (float x : v) {
    if (runs.empty() || runs.back().first != x) runs.push_back({x, 0});
    ++runs.back().second;
  }
  runs.pop_back();  // the last run is cut by the end of the phase
  int shortest = 1 << 30, longest = 0;
  for (const auto& r : runs) {
    shortest = std::min(shortest, r.second);
    longest = std::max(longest, r.second);
  }
  EXPECT_GE(shortest, fw::ValidationExcitation::kMinHold);
  EXPECT_LE(longest, 2 * fw::ValidationExcitation::kMaxHold);
  // Small reversals a -> b -> a between neighbouring levels, up and down, and steps from both extremes.
  const auto index = [&](float x) {
    for (int i = 0; i < gen.level_count(); ++i) {
      if (gen.level(i) == x) return i;
    }
    return -1;
  };
  int reversals_up = 0, reversals_down = 0, from_min = 0, from_max = 0;
  for (std::size_t k = 0; k + 2 < runs.size(); ++k) {
    const int a = index(runs[k].first), b = index(runs[k + 1].first), c = index(runs[k + 2].first);
    ASSERT_GE(a, 0);
    if (a == c && b == a + 1) ++reversals_up;
    if (a == c && b == a - 1) ++reversals_down;
    if (a == 0 && b > 1) ++from_min;
    if (a == 4 && b < 3) ++from_max;
  }
  EXPECT_GT(reversals_up, 20);
  EXPECT_GT(reversals_down, 20);
  EXPECT_GT(from_min, 20);
  EXPECT_GT(from_max, 20);
  // Seeded: the same seed gives the same sequence, another seed another one.
  fw::ValidationExcitation again(d);
  fw::RunDesign other = d;
  other.val_seed = 4;
  fw::ValidationExcitation different(other);
  int same = 0, differ = 0;
  for (float x : v) {
    same += again.next() == x ? 1 : 0;
    differ += different.next() != x ? 1 : 0;
  }
  EXPECT_EQ(same, 20000);
  EXPECT_GT(differ, 5000);
}

}  // namespace
