// The search that starts from a hint (lashid/plant/nearby_search.hpp) and the border values built on it: the
// oracles are the standard library's binary search and the same Border's values without a hint.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "lashid/plant/border.hpp"
#include "lashid/plant/nearby_search.hpp"

namespace lashid::sim {
namespace {

// A small LCG: deterministic and library-independent.
class Draws {
 public:
  explicit Draws(std::uint64_t seed) : state_(seed) {}
  double uniform(double lo, double hi) {
    state_ = state_ * 6364136223846793005ULL + 1442695040888963407ULL;
    return lo + (hi - lo) * (static_cast<double>(state_ >> 11) * 0x1.0p-53);
  }
  std::size_t index(std::size_t n) { return static_cast<std::size_t>(uniform(0.0, static_cast<double>(n))) % n; }

 private:
  std::uint64_t state_;
};

// Sorted tables with repeated values (ties: the index is the one after the last equal element), sizes 1 to 40.
std::vector<double> sorted_table(Draws& draws) {
  const std::size_t n = 1 + draws.index(40);
  std::vector<double> xs;
  for (std::size_t i = 0; i < n; ++i) {
    xs.push_back(i > 0 && draws.uniform(0.0, 1.0) < 0.2 ? xs.back() : static_cast<double>(draws.index(30)));
  }
  std::sort(xs.begin(), xs.end());
  return xs;
}

// A query: a table value exactly, a point between, or beyond either end.
double query(Draws& draws, const std::vector<double>& xs) {
  const double pick = draws.uniform(0.0, 1.0);
  if (pick < 0.4) return xs[draws.index(xs.size())];
  if (pick < 0.9) return draws.uniform(xs.front() - 0.5, xs.back() + 0.5);
  return pick < 0.95 ? xs.front() - 3.0 : xs.back() + 3.0;
}

std::size_t standard_upper(const std::vector<double>& xs, double v) {
  return static_cast<std::size_t>(std::upper_bound(xs.begin(), xs.end(), v) - xs.begin());
}

TEST(NearbySearch, GivesTheStandardUpperBoundFromAnyHint) {
  Draws draws(5101);
  int far = 0;  // queries whose answer is more than two places from the hint: the binary-search fallback
  for (int table = 0; table < 300; ++table) {
    const std::vector<double> xs = sorted_table(draws);
    std::size_t walk = 0;  // a hint carried from query to query, as an operator carries it
    for (int q = 0; q < 60; ++q) {
      const double v = query(draws, xs);
      std::size_t hint = draws.index(xs.size() + 3);  // also beyond the end
      const std::size_t start = hint;
      const std::size_t upper = standard_upper(xs, v);
      ASSERT_EQ(upper_bound_near(xs, v, hint), upper) << "table " << table << " query " << q;
      EXPECT_EQ(hint, upper);
      far += upper + 2 < start || start + 2 < upper;
      ASSERT_EQ(upper_bound_near(xs, v, walk), upper);
    }
  }
  EXPECT_GT(far, 2000);  // the fallback is exercised, not only the neighbours
}

TEST(NearbySearch, BorderValuesWithAHintAreTheValuesWithout) {
  // A table with a jump and a non-monotone stretch, walked by a slowly moving input (the operators' case) and
  // by jumps across the whole domain and beyond it.
  const Border border = Border::from_table(
      {{-1.0, -1.0}, {-0.6, -0.2}, {-0.2, -0.5}, {0.1, 0.3}, {0.1, 0.8}, {0.4, 0.6}, {0.7, 0.9}, {1.0, 1.0}});
  Draws draws(5102);
  Border::Hint hint;
  double v = 0.0;
  for (int i = 0; i < 20000; ++i) {
    v = draws.uniform(0.0, 1.0) < 0.9 ? std::clamp(v + draws.uniform(-0.05, 0.05), -1.3, 1.3)
                                      : draws.uniform(-1.3, 1.3);
    ASSERT_EQ(border(v, hint), border(v)) << "draw " << i;
  }
  // Exactly at the points, the jump's abscissa included (its value is the right-hand point's, 0.8).
  for (const double x : {-1.0, -0.6, -0.2, 0.1, 0.4, 0.7, 1.0, 0.1, -1.0}) ASSERT_EQ(border(x, hint), border(x));
  EXPECT_EQ(border(0.1, hint), 0.8);
}

}  // namespace
}  // namespace lashid::sim
