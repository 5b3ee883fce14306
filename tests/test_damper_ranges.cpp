// Damper data beyond what a double can hold as a span (issue 14, section 6: found by hand): refused where it is read,
// naming the file, line and column; refused by the fits for records made in memory; and every window computed from
// the data well-defined. Split from test_operator_fit.cpp, which tests the fits themselves.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "data_error_matchers.hpp"
#include "lashid/io/damper_data.hpp"
#include "lashid/operator_fit/operator_fit.hpp"
#include "lashid/operator_fit/output_dynamics.hpp"

namespace damper_ranges_test {

using namespace lashid::sim;
using lashid::test::Contains;
using lashid::test::error_of;

const std::string kHeader = "t_s,x_in,F_kip,v_in_per_s\n";

// Issue 14 section 6: x_in near +1e308 and -1e308 spans more than the double range (max - min = inf), and a bin
// index computed from that span was undefined behaviour. Such a value is refused where it is read, naming the file,
// the line and the column; so is any value beyond kDamperValueLimit, in every column.
TEST(DamperData, ValueBeyondTheLimitNamesLineAndColumn) {
  const std::string e = error_of([] { parse_damper_csv(kHeader + "0,1e308,0,0\n0.1,-1e308,0,0\n", "a.csv"); });
  EXPECT_TRUE(Contains(e, "a.csv:2: column 'x_in': 1e+308 is beyond 1e+12 in magnitude")) << e;
  EXPECT_TRUE(Contains(e, "within the double range): not a displacement in inches")) << e;
  const std::string force = error_of([] { parse_damper_csv(kHeader + "0,0,0,0\n0.1,0,-2e12,0\n", "a.csv"); });
  EXPECT_TRUE(Contains(force, "a.csv:3: column 'F_kip': -2e+12 is beyond 1e+12")) << force;
  EXPECT_TRUE(Contains(force, "not a force in kip")) << force;
  const std::string time = error_of([] { parse_damper_csv(kHeader + "-1e300,0,0,0\n", "a.csv"); });
  EXPECT_TRUE(Contains(time, "a.csv:2: column 't_s'")) << time;
  // At the limit itself a file is read.
  EXPECT_EQ(parse_damper_csv(kHeader + "0,1e12,-1e12,0\n", "a.csv").v.front(), 1e12);
}

// The fits apply the same rule to records made in memory, before any span or bin index is computed.
TEST(OperatorFit, FitsRefuseARecordSpanningMoreThanTheDoubleRange) {
  DamperRecord rec;
  rec.source = "wide.csv";
  rec.v = {1e308, -1e308, 1e308, -1e308};
  rec.u = {1, -1, 1, -1};
  rec.t = {0, 1, 2, 3};
  const std::vector<DamperRecord> train{rec};
  for (const std::string& e : {error_of([&] { fit_nominal(train, {}); }), error_of([&] { fit_extended(train, {}); }),
                               error_of([&] { fit_curve_at_width(train, 0.1, {}); })}) {
    EXPECT_TRUE(Contains(e, "wide.csv: sample 0: column 'v': 1e+308 is beyond 1e+12 in magnitude")) << e;
  }
  // A border over a span that is not finite is refused; a NaN abscissa inside a finite span goes to node 0.
  const std::vector<std::pair<double, double>> wide{{1e308, 1.0}, {-1e308, 2.0}};
  EXPECT_THROW(fit_border(wide, -1e308, 1e308, 41), std::invalid_argument);
  const std::vector<std::pair<double, double>> with_nan{{std::nan(""), 1.0}, {1.0, 2.0}};
  EXPECT_EQ(fit_border(with_nan, 0.0, 1.0, 3)(0.0), 1.0);
}

// A time step so small that 25 ms is more samples than a size_t holds: the speed window is clamped to the record.
TEST(LoopAnalysis, TinyTimeStepIsWellDefined) {
  DamperRecord rec;
  rec.v.resize(400);
  for (std::size_t t = 0; t < rec.v.size(); ++t) rec.v[t] = std::sin(0.05 * static_cast<double>(t));
  rec.u = rec.v;
  rec.t.resize(rec.v.size());
  for (std::size_t t = 0; t < rec.t.size(); ++t) rec.t[t] = 1e-300 * static_cast<double>(t);
  const LoopAnalysis a = analyse_loop(rec, rec.u, LoopPhaseOptions{});
  ASSERT_EQ(a.phases.size(), kLoopPhaseNames.size());
  // The simulation is the measurement: no error in any phase. sin(0.05 t) turns where 0.05 t = pi/2 + k pi, at
  // t = 31.4, 94.2, 157.1, 219.9, 282.7 and 345.6 within the 400 samples: 6 reversals.
  for (const PhaseError& p : a.phases) EXPECT_EQ(p.rms, 0.0) << p.phase;
  EXPECT_EQ(a.reversals, 6U);
  // With the window clamped to the record, the slow part is the record's mean: the fast share is
  // sum (e - mean)^2 / sum e^2 of e = sin(0.05 t).
  const ErrorOscillation osc = error_oscillation(rec.u, std::vector<double>(rec.u.size(), 0.0), 1e300);
  double mean = 0, total = 0, about_mean = 0;
  for (double e : rec.u) mean += e / static_cast<double>(rec.u.size());
  for (double e : rec.u) {
    total += e * e;
    about_mean += (e - mean) * (e - mean);
  }
  EXPECT_NEAR(osc.fast_share, about_mean / total, 1e-12);
}

}  // namespace damper_ranges_test
