// Lateral borders (paper Section 2.1): tables and callable borders, their values and the crossings of a level that
// the switch and backlash laws ask for. Every expected value is derived in the comments or from an independent
// source (the range of a sine, the same table cut into pieces), not from running the code.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "lashid/plant/border.hpp"

namespace lashid::sim {
namespace {

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
// into pieces of at most 7 segments (too short to skip anything; a jump at the table's end stays with the segments
// before it), each asked on its part of [a, b]; the last reach is
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
    for (std::size_t first = 0; first + 1 < points.size();) {
      std::size_t last = std::min(first + 6, points.size() - 1);
      // A jump left alone at the end would be a piece of zero width (which from_table refuses): it joins this one.
      if (last + 2 == points.size() && points[last].first == points[last + 1].first) ++last;
      std::vector<std::pair<double, double>> piece(points.begin() + static_cast<std::ptrdiff_t>(first),
                                                   points.begin() + static_cast<std::ptrdiff_t>(last) + 1);
      pieces.push_back(Border::from_table(piece));
      first = last;  // the next piece starts at this one's last point
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
      // reaches() answers from the range of the values over [a, b], the reaches above by scanning the segments:
      // also beyond the domain, where the border is constant at its end values.
      const double ea = a - unit(rng), eb = b + unit(rng);
      ASSERT_EQ(whole.reaches(level, ea, eb, Border::Scan::from_right), whole.last_reach(level, ea, eb).has_value());
      ASSERT_EQ(whole.reaches(level, ea, b, Border::Scan::from_left), whole.first_reach(level, ea, b).has_value());
      ASSERT_EQ(whole.reaches(level, a, eb, Border::Scan::from_left), whole.first_reach(level, a, eb).has_value());
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

}  // namespace
}  // namespace lashid::sim
