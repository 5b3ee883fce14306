// Fit profiles of the damper model over a test record's unknowns (test_profiles.hpp): on records simulated from a
// known operator, started from a known slider position or at a known tension, the profile's best value is that
// truth and its fit is 100 % (the simulation is then exact: fit = 100 (1 - 0 / ||u - mean||)).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "lashid/operator_fit/test_profiles.hpp"

namespace test_profiles_test {

using namespace lashid::sim;

// G on [-r, r]: a gap at zero, a non-flat engagement on each side (so the slider's offset is visible in the force).
std::vector<std::pair<double, double>> curve(double r, double up, double down) {
  return {{-r, down}, {-0.4 * r, 0.3 * down}, {-0.1 * r, 0.0}, {0.1 * r, 0.0}, {0.4 * r, 0.3 * up}, {r, up}};
}

const OutputFilter kIdentity{{}, {1.0}};

// A sine of growing amplitude through `op`, whose slider is first placed at `offset` (u[0] from that state).
DamperRecord record_of(FrictionGapOperator op, double offset, const std::string& name) {
  DamperRecord rec;
  rec.source = name;
  op.place(0.0, offset);
  for (int t = 0; t < 4000; ++t) {
    const double v = (0.02 + 0.3 * t / 4000.0) * std::sin(2 * 3.14159265358979 * 3 * t / 4000.0);
    rec.t.push_back(t / 1000.0);
    rec.v.push_back(v);
    rec.u.push_back(op.step(v));
  }
  return rec;
}

TEST(TestProfiles, InitialOffsetProfilePeaksAtTheTrueStart) {
  const FrictionGapOperator op(Border::from_table(curve(0.2, 2.0, -3.0)), 0.0);
  // 41 values over [-0.2, 0.2]: step 0.01, so 0.07 is the 28th (index 27).
  const DamperRecord rec = record_of(op, 0.07, "synthetic");
  const FitProfile p = initial_offset_profile(op, kIdentity, rec, 41);
  EXPECT_EQ(p.parameter, "initial_offset_in");
  ASSERT_EQ(p.points.size(), 41U);
  EXPECT_DOUBLE_EQ(p.points.front().first, -0.2);
  EXPECT_DOUBLE_EQ(p.points.back().first, 0.2);
  EXPECT_NEAR(p.best_value, 0.07, 1e-12);
  EXPECT_NEAR(p.best_fit, 100.0, 1e-9);
  // A start on the other side of the gap is visibly worse: the test can tell the offsets apart.
  EXPECT_LT(p.points[5].second, 99.0);
}

TEST(TestProfiles, TensionProfilePeaksAtTheRecordsTensionAndSkipsInvalidExtrapolation) {
  TensionFrictionFit fit;
  // r shrinks with tension, 0.2 at 30 lb and 0.1 at 36 lb: beyond 42 lb it would be <= 0 (no operator there).
  fit.tensions.push_back({30.0, 0.2, {}, 0.0, 1, {}});
  fit.tensions.push_back({36.0, 0.1, {}, 0.0, 1, {}});
  // G on 21 equally spaced nodes of [-r, r] (the layout at() interpolates node by node).
  for (auto& c : fit.tensions) {
    const double up = c.tension_lb / 10, down = -c.tension_lb / 8;
    const Border g = Border::from_table(curve(c.half_width, up, down));
    for (int n = 0; n <= 20; ++n) {
      const double e = -c.half_width + 2 * c.half_width * n / 20.0;
      c.curve.emplace_back(e, g(e));
    }
  }
  const auto truth = fit.make(33.0);
  const DamperRecord rec = record_of(*truth, 0.0, "at33lb");
  const FitProfile p = tension_profile(fit, kIdentity, rec, 24.0, 48.0, 1.0);
  EXPECT_EQ(p.parameter, "tension_lb");
  // 24..41 lb: r = 0.2 - (T - 30) / 60 > 0; at 42 lb and beyond the play is empty: left out.
  ASSERT_EQ(p.points.size(), 18U);
  EXPECT_DOUBLE_EQ(p.points.back().first, 41.0);
  EXPECT_DOUBLE_EQ(p.best_value, 33.0);
  EXPECT_NEAR(p.best_fit, 100.0, 1e-9);
  EXPECT_DOUBLE_EQ(p.points[9].first, 33.0);
  EXPECT_LT(p.points[8].second, p.best_fit);  // 32 lb, beside it, is worse, and 30 lb (index 6) clearly
  EXPECT_LT(p.points[6].second, 99.0);
}

TEST(TestProfiles, BadArgumentsAreErrorsNamingTheRecord) {
  const FrictionGapOperator op(Border::from_table(curve(0.2, 2.0, -3.0)), 0.0);
  const DamperRecord rec = record_of(op, 0.0, "named.csv");
  EXPECT_THROW(initial_offset_profile(op, kIdentity, rec, 1), std::invalid_argument);
  DamperRecord one = rec;
  one.t.resize(1);
  one.v.resize(1);
  one.u.resize(1);
  try {
    initial_offset_profile(op, kIdentity, one, 5);
    ADD_FAILURE() << "a one-sample record was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("named.csv"), std::string::npos) << e.what();
  }
  TensionFrictionFit fit;
  fit.tensions.push_back({30.0, 0.2, curve(0.2, 2, -3), 0.0, 1, {}});
  fit.tensions.push_back({36.0, 0.2, curve(0.2, 2, -3), 0.0, 1, {}});
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (auto [lo, hi, step] : {std::tuple{36.0, 30.0, 1.0}, std::tuple{30.0, 36.0, 0.0}, std::tuple{-1.0, 36.0, 1.0},
                              std::tuple{nan, 36.0, 1.0}, std::tuple{30.0, 36.0, nan}}) {
    EXPECT_THROW(tension_profile(fit, kIdentity, rec, lo, hi, step), std::invalid_argument) << lo << " " << hi;
  }
  EXPECT_THROW(FrictionGapOperator(op).place(nan, 0.0), std::invalid_argument);
}

}  // namespace test_profiles_test
