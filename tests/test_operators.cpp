// Hysteresis operators against hand-computed sequences (paper Section 2.1, (2.3)-(2.4)); the borders' own tests are
// in test_border.cpp.
// Every expected value below is derived in the comments from the border formulas, not from running the code.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <vector>

#include "lashid/plant/border.hpp"
#include "lashid/plant/operators.hpp"

namespace lashid::sim {
namespace {

constexpr double kExact = 1e-12;

// Steps `op` through `inputs` and checks each output against `expected`.
void expect_sequence(HysteresisOperator& op, const std::vector<double>& inputs, const std::vector<double>& expected,
                     double tolerance = kExact) {
  ASSERT_EQ(inputs.size(), expected.size());
  for (std::size_t t = 0; t < inputs.size(); ++t) {
    EXPECT_NEAR(op.step(inputs[t]), expected[t], tolerance) << "step " << t << ", v = " << inputs[t];
  }
}

// -------------------------------------------------------------------------------------------------- switch

TEST(SwitchOperator, JumpsBetweenBordersAndHoldsOnRepeatedInput) {
  // C_a(v) = v - 1, C_d(v) = 2v + 1. From (0, 7): up -> C_a, down -> C_d, equal -> hold.
  SwitchOperator op(Border::from_function([](double v) { return v - 1.0; }, -5.0, 5.0),
                    Border::from_function([](double v) { return 2.0 * v + 1.0; }, -5.0, 5.0));
  op.reset(0.0, 7.0);
  expect_sequence(op, {0.0, 1.0, 2.0, 1.5, 1.5, 3.0, 0.0, -1.0, -0.5},
                  {7.0, 0.0, 1.0, 4.0, 4.0, 2.0, 1.0, -1.0, -1.5});
  EXPECT_EQ(op.name(), "switch");
}

// ------------------------------------------------------------------------------------------------ backlash

Border play_ascending() { return Border::from_function([](double v) { return v - 1.0; }, -10.0, 10.0); }
Border play_descending() { return Border::from_function([](double v) { return v + 1.0; }, -10.0, 10.0); }

TEST(BacklashOperator, ClassicPlayUpDownAndReversals) {
  // C_a = v - 1, C_d = v + 1. From (0, 0), inside the band.
  BacklashOperator op(play_ascending(), play_descending());
  op.reset(0.0, 0.0);
  expect_sequence(op,
                  // up: C_a^{-1}(0) = 1 not yet reached; then reached; on C_a; reverse: C_d^{-1}(2) = 1 not reached
                  {0.5, 2.0, 3.0, 2.0, 1.5,
                   // reached at 0.5 <= 1; on C_d; reverse: C_a^{-1}(0) = 1 not reached; repeat; reach and follow
                   0.5, -1.0, 0.0, 0.0, 5.0, -10.0},
                  {0.0, 1.0, 2.0, 2.0, 2.0, 1.5, 0.0, 0.0, 0.0, 4.0, -9.0});
  EXPECT_EQ(op.name(), "backlash");
}

TEST(BacklashOperator, PlayMatchesClosedFormWithFunctionAndTableBorders) {
  // Inside the band the play operator is u = max(v - 1, min(v + 1, u_prev)).
  BacklashOperator with_functions(play_ascending(), play_descending());
  BacklashOperator with_tables(Border::from_table({{-10.0, -11.0}, {10.0, 9.0}}),
                               Border::from_table({{-10.0, -9.0}, {10.0, 11.0}}));
  with_functions.reset(0.0, 0.0);
  with_tables.reset(0.0, 0.0);
  double u = 0.0;
  for (int t = 0; t < 2000; ++t) {
    const double v = 6.0 * std::sin(0.37 * t) + 2.0 * std::sin(1.3 * t) + (t % 7 == 0 ? 0.5 : 0.0);
    u = std::max(v - 1.0, std::min(v + 1.0, u));
    EXPECT_NEAR(with_functions.step(v), u, kExact) << "t = " << t;
    EXPECT_NEAR(with_tables.step(v), u, 1e-12) << "t = " << t;
  }
}

TEST(BacklashOperator, RelayWithDiscontinuousNonMonotoneTableBorders) {
  // Fig. 6 style. C_a: -1 up to v = 1, jumps to 1, drops to 0.5 at v = 2. C_d: -1 up to v = -1, then 1.
  BacklashOperator op(Border::from_table({{-3.0, -1.0}, {1.0, -1.0}, {1.0, 1.0}, {2.0, 1.0}, {2.0, 0.5}, {3.0, 0.5}}),
                      Border::from_table({{-3.0, -1.0}, {-1.0, -1.0}, {-1.0, 1.0}, {3.0, 1.0}}));
  op.reset(-3.0, -1.0);  // bottom-left corner, on both borders
  expect_sequence(op,
                  {0.0,    // on C_a: -1
                   1.0,    // C_a(1) = 1 (right-continuous jump)
                   1.5,    // 1
                   2.5,    // C_a(2.5) = 0.5: the output drops while v rises (non-monotone border)
                   0.0,    // C_d^{-1}(0.5) ∩ [0, 2.5] = {} (C_d = 1 there): hold 0.5
                   -1.0,   // the jump of C_d at -1 spans [-1, 1] ∋ 0.5: u = C_d(-1) = 1
                   -2.0,   // on C_d: -1
                   2.0,    // C_a^{-1}(-1) contains -2: u = C_a(2) = 0.5
                   1.5,    // C_d^{-1}(0.5) ∩ [1.5, 2] = {}: hold
                   1.8,    // C_a^{-1}(0.5) ∩ [1.5, 1.8] = {} (C_a = 1 there): hold
                   2.5,    // the jump of C_a at 2 spans [0.5, 1] ∋ 0.5: u = C_a(2.5) = 0.5
                   0.5,    // C_d^{-1}(0.5) ∩ [0.5, 2.5] = {}: hold
                   -1.5},  // jump at -1 is in [-1.5, 0.5]: u = C_d(-1.5) = -1
                  {-1.0, 1.0, 1.0, 0.5, 0.5, 1.0, -1.0, 0.5, 0.5, 0.5, 0.5, 0.5, -1.0});
}

TEST(BacklashOperator, ClassicRelayThresholds) {
  // C_a switches to 1 at v = 1, C_d switches to -1 below v = -1 (right-continuous: C_d(-1) = 1).
  BacklashOperator op(Border::from_table({{-3.0, -1.0}, {1.0, -1.0}, {1.0, 1.0}, {3.0, 1.0}}),
                      Border::from_table({{-3.0, -1.0}, {-1.0, -1.0}, {-1.0, 1.0}, {3.0, 1.0}}));
  op.reset(-3.0, -1.0);
  expect_sequence(op, {0.0, 0.999, 1.0, 2.0, 0.0, -0.999, -1.0, -1.001, 0.5, 1.0},
                  {-1.0, -1.0, 1.0, 1.0, 1.0, 1.0, 1.0, -1.0, -1.0, 1.0});
}

TEST(BacklashOperator, CrossingBordersFollowTheLiteralLaw) {
  // Fig. 4 style: C_d = v + 1, C_a = v^3/4 + 1 on [-2, 2]; they cross at v = 0 (and meet at ±2).
  // For v > 0, C_a < C_d (ordinary orientation); for v < 0, C_a > C_d (inverted).
  BacklashOperator op(Border::from_function([](double v) { return v * v * v / 4.0 + 1.0; }, -2.0, 2.0),
                      Border::from_function([](double v) { return v + 1.0; }, -2.0, 2.0));
  op.reset(-2.0, -1.0);  // C_a(-2) = C_d(-2) = -1
  expect_sequence(op,
                  {-1.0,   // on C_a: -1/4 + 1 = 0.75
                   1.0,    // on C_a: 1.25
                   0.5,    // C_d^{-1}(1.25) = {0.25} not in [0.5, 1]: hold 1.25
                   0.0,    // 0.25 in [0, 0.5]: C_d(0) = 1
                   -1.0,   // on C_d: 0
                   0.0,    // C_a^{-1}(0) = {-cbrt(4)} = {-1.587...} not in [-1, 0]: hold 0
                   2.0,    // still not in [0, 2]: hold 0 -- the point (2, 0) is below both borders
                   -1.5,   // C_d^{-1}(0) = {-1} in [-1.5, 2]: C_d(-1.5) = -0.5
                   2.0,    // C_a^{-1}(-0.5) = {-cbrt(6)} = {-1.817...} not in [-1.5, 2]: hold -0.5
                   -2.0,   // C_d^{-1}(-0.5) = {-1.5} in [-2, 2]: C_d(-2) = -1
                   1.0},   // C_a^{-1}(-1) = {-2}: C_a(1) = 1.25
                  {0.75, 1.25, 1.25, 1.0, 0.0, 0.0, 0.0, -0.5, -0.5, -1.0, 1.25});
}

TEST(BacklashOperator, CoincidentBordersActAsStaticNonlinearity) {
  const Border smooth = Border::from_function([](double v) { return std::sin(v) + 0.3 * v; }, -5.0, 5.0);
  const Border jumpy = Border::from_table({{-5.0, 2.0}, {-1.0, -1.0}, {0.0, 0.5}, {0.0, -2.0}, {2.0, 3.0}, {5.0, 1.0}});
  for (const Border& border : {smooth, jumpy}) {
    BacklashOperator op(border, border);
    op.reset(-5.0, border(-5.0));
    for (int t = 0; t < 500; ++t) {
      const double v = (t % 11 == 3) ? 0.0 : 4.9 * std::sin(0.21 * t) * std::cos(0.05 * t);
      EXPECT_DOUBLE_EQ(op.step(v), border(v)) << "t = " << t << ", table = " << border.is_table();
    }
  }
}

TEST(BacklashOperator, TooNarrowIntervalFreezesAfterOneCycle) {
  // Fig. 5 / Remark 1(b): C_a = v - 1, C_d = v + 1 on [-0.5, 0.5]. Starting on C_a at v_m, the first sweep up
  // follows C_a to u_M = C_a(0.5) = -0.5. Going down, C_d^{-1}(-0.5) = {-1.5} is outside the interval, so u
  // holds; going up again C_a^{-1}(-0.5) = {0.5} is only reached at v_M where C_a(v_M) = u_M. u stays -0.5.
  auto ascending = Border::from_function([](double v) { return v - 1.0; }, -0.5, 0.5);
  auto descending = Border::from_function([](double v) { return v + 1.0; }, -0.5, 0.5);
  BacklashOperator op(ascending, descending);
  op.reset(-0.5, -1.5);
  expect_sequence(op, {-0.25, 0.0, 0.25, 0.5}, {-1.25, -1.0, -0.75, -0.5});
  for (int cycle = 0; cycle < 5; ++cycle) {
    expect_sequence(op, {0.25, 0.0, -0.25, -0.5, -0.25, 0.0, 0.25, 0.5}, std::vector<double>(8, -0.5), 0.0);
  }
  // Same borders on the wide interval [-2, 2] exhibit the full cycle: -1 at v_m and +1 at v_M every time.
  BacklashOperator wide(Border::from_function([](double v) { return v - 1.0; }, -2.0, 2.0),
                        Border::from_function([](double v) { return v + 1.0; }, -2.0, 2.0));
  wide.reset(-2.0, -3.0);
  for (int cycle = 0; cycle < 3; ++cycle) {
    // up: C_a^{-1}(-1) = {0}; hold -1 until 0, then 0 -> 1 ; down: C_d^{-1}(1) = {0}; hold 1, then 0 -> -1
    expect_sequence(wide, {-1.0, 0.0, 1.0, 2.0, 1.0, 0.0, -1.0, -2.0},
                    {cycle == 0 ? -2.0 : -1.0, -1.0, 0.0, 1.0, 1.0, 1.0, 0.0, -1.0});
  }
}

TEST(BacklashOperator, PaperDisExamplePulsesFromVmax) {
  // (3.29)/(3.32): C_d(v) = (v^3 + 3.5 v^2 + 2.75 v + 4.625)/70.5, C_a(v) = C_d(v - 1), on [-3, 4].
  // By hand (numerators): C_d(-3) = 0.875, C_d(-2) = 5.125, C_d(-1) = 4.375, C_d(1) = 11.875, C_d(2) = 32.125,
  // C_d(3) = 71.375 = C_a(4). C_d < 71.375 on [-3, 3) (its local max is ~5.18 at v = -11/6), so going down
  // from (4, 71.375/70.5) meets C_d at v = 3 only, and any V <= 3 gives u = C_d(V). Going back up from
  // (V, C_d(V)), C_a starts at C_a(V) = C_d(V-1) and ends at 71.375/70.5 >= C_d(V); e.g. for V = -1 the level
  // 4.375 is met by C_d(w) at w = -1, i.e. C_a at v = 0 <= 4. So u = C_a(4) on every return.
  auto descending_polynomial = [](double v) { return (v * v * v + 3.5 * v * v + 2.75 * v + 4.625) / 70.5; };
  BacklashOperator op(Border::from_function([=](double v) { return descending_polynomial(v - 1.0); }, -3.0, 4.0),
                      Border::from_function(descending_polynomial, -3.0, 4.0));
  op.reset(-3.0, 0.875 / 70.5);
  const double u_max = 71.375 / 70.5;
  EXPECT_NEAR(op.step(4.0), u_max, kExact);
  const std::vector<std::pair<double, double>> pulses = {{-3.0, 0.875},  {-2.0, 5.125}, {-1.0, 4.375},
                                                         {1.0, 11.875},  {2.0, 32.125}, {3.0, 71.375}};
  for (int round = 0; round < 2; ++round) {
    for (const auto& [level_v, numerator] : pulses) {
      EXPECT_NEAR(op.step(level_v), numerator / 70.5, kExact) << "pulse to " << level_v;
      EXPECT_NEAR(op.step(4.0), u_max, kExact) << "return from " << level_v;
      EXPECT_NEAR(op.step(4.0), u_max, kExact) << "hold after " << level_v;
    }
  }
}

TEST(BacklashOperator, CloneCarriesTheState) {
  BacklashOperator op(play_ascending(), play_descending());
  op.reset(0.0, 0.0);
  op.step(3.0);  // on C_a: 2
  const auto copy = op.clone();
  // Both continue identically: down to 2 holds 2, down to 0 follows C_d: 1.
  EXPECT_DOUBLE_EQ(op.step(2.0), 2.0);
  EXPECT_DOUBLE_EQ(copy->step(2.0), 2.0);
  EXPECT_DOUBLE_EQ(op.step(0.0), 1.0);
  EXPECT_DOUBLE_EQ(copy->step(0.0), 1.0);
}

TEST(BacklashOperator, NanInputThrows) {
  BacklashOperator op(play_ascending(), play_descending());
  EXPECT_THROW(op.step(std::numeric_limits<double>::quiet_NaN()), std::invalid_argument);
}

// ----------------------------------------------------------------------------------- input-side wrappers

TEST(InputLagOperator, LambdaZeroEqualsInner) {
  BacklashOperator reference(play_ascending(), play_descending());
  InputLagOperator lagged(std::make_unique<BacklashOperator>(play_ascending(), play_descending()), 0.0);
  reference.reset(0.0, 0.0);
  lagged.reset(0.0, 0.0);
  for (int t = 0; t < 300; ++t) {
    const double v = 7.0 * std::sin(0.13 * t);
    EXPECT_EQ(lagged.step(v), reference.step(v)) << "t = " << t;
  }
  EXPECT_EQ(lagged.name(), "input_lag(backlash)");
}

TEST(InputLagOperator, FirstOrderFilterBeforeTheOperator) {
  // Inner: coincident borders 2v, so u = 2 w. w(t) = 0.5 w(t-1) + 0.5 v(t) from rest at 0:
  // v = 1, 1, 1, -1 -> w = 0.5, 0.75, 0.875, -0.0625 -> u = 1, 1.5, 1.75, -0.125.
  const Border twice = Border::from_function([](double v) { return 2.0 * v; }, -5.0, 5.0);
  InputLagOperator lagged(std::make_unique<BacklashOperator>(twice, twice), 0.5);
  lagged.reset(0.0, 0.0);
  expect_sequence(lagged, {1.0, 1.0, 1.0, -1.0}, {1.0, 1.5, 1.75, -0.125});
  EXPECT_THROW(InputLagOperator(std::make_unique<BacklashOperator>(twice, twice), 1.0), std::invalid_argument);
  EXPECT_THROW(InputLagOperator(nullptr, 0.1), std::invalid_argument);
}

TEST(DeadTimeOperator, ShiftsTheInputByDSamples) {
  // Inner switch with coincident borders v + 10 is static: u(t) = v(t - 3) + 10, with v(t < 0) = 2 (reset).
  const Border shifted = Border::from_function([](double v) { return v + 10.0; }, -10.0, 10.0);
  DeadTimeOperator delayed(std::make_unique<SwitchOperator>(shifted, shifted), 3);
  delayed.reset(2.0, 12.0);
  expect_sequence(delayed, {5.0, -1.0, 4.0, 0.0, 7.0, 7.0, 1.0}, {12.0, 12.0, 12.0, 15.0, 9.0, 14.0, 10.0});
  const auto copy = delayed.clone();  // queue holds 7, 7, 1 (oldest first)
  expect_sequence(*copy, {3.0, 3.0, 3.0, 3.0}, {17.0, 17.0, 11.0, 13.0});

  DeadTimeOperator no_delay(std::make_unique<SwitchOperator>(shifted, shifted), 0);
  no_delay.reset(2.0, 12.0);
  expect_sequence(no_delay, {5.0, -1.0}, {15.0, 9.0});
  EXPECT_EQ(no_delay.name(), "dead_time(switch)");
  EXPECT_THROW(DeadTimeOperator(std::make_unique<SwitchOperator>(shifted, shifted), -1), std::invalid_argument);
}

}  // namespace
}  // namespace lashid::sim
