// Borders and hysteresis operators against hand-computed sequences (paper Section 2.1, (2.3)-(2.4)).
// Every expected value below is derived in the comments from the border formulas, not from running the code.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <cstdint>
#include <memory>
#include <optional>
#include <random>
#include <stdexcept>
#include <string>
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

std::string message_of_table_error(std::vector<std::pair<double, double>> points) {
  try {
    (void)Border::from_table(std::move(points));
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  return "(no exception)";
}

// ------------------------------------------------------------------------------------------------- borders

TEST(BorderTable, ValuesAreLinearBetweenPointsRightContinuousAtJumpsAndClampedOutside) {
  // C = v on [0,1), jumps to 3 at v = 1, then slope 1 up to (3, 5).
  const Border border = Border::from_table({{0.0, 0.0}, {1.0, 1.0}, {1.0, 3.0}, {3.0, 5.0}});
  EXPECT_DOUBLE_EQ(border(0.5), 0.5);
  EXPECT_DOUBLE_EQ(border(1.0), 3.0);  // last point at the jump abscissa
  EXPECT_DOUBLE_EQ(border(2.0), 4.0);
  EXPECT_DOUBLE_EQ(border(-7.0), 0.0);
  EXPECT_DOUBLE_EQ(border(9.0), 5.0);
  EXPECT_DOUBLE_EQ(border.lo(), 0.0);
  EXPECT_DOUBLE_EQ(border.hi(), 3.0);
}

TEST(BorderTable, BadTablesThrowNamingTheIndex) {
  EXPECT_NE(message_of_table_error({{0.0, 1.0}}).find("at least 2 points"), std::string::npos);
  EXPECT_NE(message_of_table_error({{0.0, 0.0}, {1.0, 0.0}, {0.5, 0.0}}).find("point 2"), std::string::npos);
  EXPECT_NE(message_of_table_error({{0.0, 0.0}, {1.0, NAN}}).find("point 1"), std::string::npos);
  EXPECT_NE(message_of_table_error({{0.0, 0.0}, {1.0, 0.0}, {1.0, 1.0}, {1.0, 2.0}}).find("point 3"),
            std::string::npos);
  EXPECT_THROW((void)Border::from_table({{1.0, 0.0}, {1.0, 2.0}}), std::invalid_argument);
  EXPECT_THROW((void)Border::from_function([](double v) { return v; }, 1.0, 1.0), std::invalid_argument);
  EXPECT_THROW((void)Border::from_function([](double v) { return 1.0 / v; }, -1.0, 1.0, 2), std::invalid_argument);
}

TEST(BorderReach, TableAndFunctionGiveTheSameCrossings) {
  // Jump: v on [0,1), v + 2 on [1,3]; the vertical segment at v = 1 covers levels [1, 3].
  const Border jump_table = Border::from_table({{0.0, 0.0}, {1.0, 1.0}, {1.0, 3.0}, {3.0, 5.0}});
  const Border jump_function = Border::from_function([](double v) { return v < 1.0 ? v : v + 2.0; }, 0.0, 3.0);
  // Non-monotone: |v - 1| on [-1, 3]; the level 1 is met at v = 0 and v = 2.
  const Border vee_table = Border::from_table({{-1.0, 2.0}, {1.0, 0.0}, {3.0, 2.0}});
  const Border vee_function = Border::from_function([](double v) { return std::abs(v - 1.0); }, -1.0, 3.0, 1000);
  // Flat on the level: 1 on [0, 2], then v - 1 up to (3, 2).
  const Border flat_table = Border::from_table({{0.0, 1.0}, {2.0, 1.0}, {3.0, 2.0}});
  const Border flat_function = Border::from_function([](double v) { return v < 2.0 ? 1.0 : v - 1.0; }, 0.0, 3.0);

  struct Case {
    const Border* table;
    const Border* function;
    double level, a, b;
    std::optional<double> last, first;
  };
  const std::vector<Case> cases = {
      {&jump_table, &jump_function, 2.0, 0.0, 3.0, 1.0, 1.0},   // inside the jump
      {&jump_table, &jump_function, 4.0, 0.0, 3.0, 2.0, 2.0},   // 4 = v + 2
      {&jump_table, &jump_function, 0.5, 0.0, 3.0, 0.5, 0.5},   // 0.5 = v
      {&jump_table, &jump_function, 2.0, 1.5, 3.0, {}, {}},     // jump excluded by the interval
      {&jump_table, &jump_function, 6.0, 0.0, 3.0, {}, {}},     // above the range
      {&vee_table, &vee_function, 1.0, -1.0, 3.0, 2.0, 0.0},
      {&vee_table, &vee_function, 1.0, -1.0, 1.5, 0.0, 0.0},
      {&vee_table, &vee_function, 1.0, 0.5, 3.0, 2.0, 2.0},
      {&vee_table, &vee_function, 0.5, -1.0, 3.0, 1.5, 0.5},
      {&vee_table, &vee_function, -1.0, -1.0, 3.0, {}, {}},
      {&flat_table, &flat_function, 1.0, 0.0, 3.0, 2.0, 0.0},
      {&flat_table, &flat_function, 1.0, 0.5, 3.0, 2.0, 0.5},
      {&flat_table, &flat_function, 1.5, 0.0, 3.0, 2.5, 2.5},
      {&flat_table, &flat_function, 1.0, -5.0, 3.0, 2.0, -5.0},  // constant extension left of lo = 0
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const Case& c = cases[i];
    for (const Border* border : {c.table, c.function}) {
      const auto last = border->last_reach(c.level, c.a, c.b);
      const auto first = border->first_reach(c.level, c.a, c.b);
      ASSERT_EQ(last.has_value(), c.last.has_value()) << "case " << i;
      ASSERT_EQ(first.has_value(), c.first.has_value()) << "case " << i;
      EXPECT_EQ(border->reaches(c.level, c.a, c.b, Border::Scan::from_right), c.last.has_value()) << "case " << i;
      EXPECT_EQ(border->reaches(c.level, c.a, c.b, Border::Scan::from_left), c.last.has_value()) << "case " << i;
      const char* kind = border->is_table() ? " table" : " function";
      if (c.last) {
        EXPECT_NEAR(*last, *c.last, 1e-11) << "case " << i << kind;
      }
      if (c.first) {
        EXPECT_NEAR(*first, *c.first, 1e-11) << "case " << i << kind;
      }
    }
  }
}

// A long table's scans skip whole blocks of segments that cannot meet the level. The oracle: the same table cut
// into pieces of at most 7 segments (too short to skip anything), each asked on its part of [a, b]; the last reach is
// the largest of the pieces' answers, the first the smallest. Random tables with jumps and flat pieces, levels on
// and between the stored values, and intervals that end on and between the abscissas.
TEST(BorderReach, LongTablesAnswerAsTheirShortPiecesDo) {
  std::mt19937_64 rng(20261127);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int hits = 0, jumps = 0;
  for (int table = 0; table < 200; ++table) {
    const int count = 20 + static_cast<int>(unit(rng) * 70);
    std::vector<std::pair<double, double>> points;
    double x = -3.0, y = 0.0;
    for (int i = 0; i < count; ++i) {
      // A jump repeats the last abscissa, unless the last two points already share it (at most two per abscissa).
      const std::size_t n = points.size();
      const bool jump = n >= 1 && (n == 1 || points[n - 2].first != x) && unit(rng) < 0.1;
      if (i > 0 && !jump) x += 0.05 + unit(rng) * 0.2;
      if (unit(rng) > 0.15) y = std::sin(x) + (unit(rng) - 0.5);  // else flat: the same value again
      points.emplace_back(x, y);
    }
    if (!(points.front().first < points.back().first)) continue;
    for (std::size_t k = 1; k < points.size(); ++k) jumps += points[k].first == points[k - 1].first;
    const Border whole = Border::from_table(points);
    std::vector<Border> pieces;
    for (std::size_t first = 0; first + 1 < points.size(); first += 7) {
      const std::size_t last = std::min(first + 7, points.size() - 1);
      std::vector<std::pair<double, double>> piece(points.begin() + static_cast<std::ptrdiff_t>(first),
                                                   points.begin() + static_cast<std::ptrdiff_t>(last) + 1);
      if (piece.front().first < piece.back().first) pieces.push_back(Border::from_table(piece));
    }
    const auto pick = [&](double lo, double hi) {
      const double u = unit(rng);
      if (u < 0.3) return points[static_cast<std::size_t>(unit(rng) * static_cast<double>(points.size() - 1))].first;
      return lo + (hi - lo) * unit(rng);
    };
    for (int query = 0; query < 200; ++query) {
      double a = pick(whole.lo(), whole.hi()), b = pick(whole.lo(), whole.hi());
      if (a > b) std::swap(a, b);
      const double level = unit(rng) < 0.3
                               ? points[static_cast<std::size_t>(unit(rng) * static_cast<double>(points.size()))].second
                               : -1.5 + 3.0 * unit(rng);
      std::optional<double> last, first;
      for (const Border& p : pieces) {
        const double pa = std::max(a, p.lo()), pb = std::min(b, p.hi());
        if (!(pa <= pb)) continue;
        if (const auto r = p.last_reach(level, pa, pb); r && (!last || *r > *last)) last = r;
        if (const auto r = p.first_reach(level, pa, pb); r && (!first || *r < *first)) first = r;
      }
      ASSERT_EQ(whole.last_reach(level, a, b), last) << "table " << table << " query " << query;
      ASSERT_EQ(whole.first_reach(level, a, b), first) << "table " << table << " query " << query;
      ASSERT_EQ(whole.reaches(level, a, b, Border::Scan::from_right), last.has_value());
      ASSERT_EQ(whole.reaches(level, a, b, Border::Scan::from_left), last.has_value());
      hits += last.has_value();
    }
  }
  EXPECT_GT(hits, 5000);  // both answers are exercised (200 x 200 queries)
  EXPECT_LT(hits, 35000);
  EXPECT_GT(jumps, 200);  // and tables with jumps (vertical segments)
}

TEST(BorderReach, OscillatingBorderAgreesWithTheRangeOfSine) {
  // C(v) = sin(7 v) on [-3, 3]: the level L is reached on [a, b] iff min <= L <= max of sin over [7a, 7b], where
  // the extremes are at the ends or at 7v = pi/2 + k pi. Exercises the block-skipping scan in both directions.
  const double pi = std::acos(-1.0);
  const Border border = Border::from_function([](double v) { return std::sin(7.0 * v); }, -3.0, 3.0);
  std::uint64_t state = 12345;
  auto uniform = [&state](double lo, double hi) {  // small LCG: deterministic and library-independent
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return lo + (hi - lo) * (static_cast<double>(state >> 11) * 0x1.0p-53);
  };
  for (int i = 0; i < 3000; ++i) {
    double a = uniform(-3.0, 3.0);
    double b = uniform(-3.0, 3.0);
    if (a > b) std::swap(a, b);
    const double level = uniform(-0.99, 0.99);
    double low = std::min(std::sin(7.0 * a), std::sin(7.0 * b));
    double high = std::max(std::sin(7.0 * a), std::sin(7.0 * b));
    for (double k = std::ceil((7.0 * a - pi / 2.0) / pi); pi / 2.0 + k * pi <= 7.0 * b; k += 1.0) {
      const bool is_max = std::fmod(std::abs(k), 2.0) == 0.0;  // sin(pi/2 + k pi) = (-1)^k
      (is_max ? high : low) = is_max ? 1.0 : -1.0;
    }
    const bool expected = low <= level && level <= high;
    ASSERT_EQ(border.reaches(level, a, b, Border::Scan::from_left), expected) << "draw " << i;
    ASSERT_EQ(border.reaches(level, a, b, Border::Scan::from_right), expected) << "draw " << i;
    const auto last = border.last_reach(level, a, b);
    const auto first = border.first_reach(level, a, b);
    ASSERT_EQ(last.has_value(), expected);
    ASSERT_EQ(first.has_value(), expected);
    if (expected) {
      EXPECT_NEAR(std::sin(7.0 * *last), level, 1e-10) << "draw " << i;
      EXPECT_NEAR(std::sin(7.0 * *first), level, 1e-10) << "draw " << i;
      EXPECT_LE(*first, *last);
    }
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
