// Measured damper records (loader), fitting of the operators to them, the friction-gap operator, the loop error
// analysis, the damper's cause rules, and the friction-gap operator as the actuator of a DIS/AIS scenario
// (docs/friction-damper.md).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "data_error_matchers.hpp"
#include "lashid/identify/identify.hpp"
#include "lashid/io/damper_data.hpp"
#include "lashid/operator_fit/damper_causes.hpp"
#include "lashid/operator_fit/operator_fit.hpp"
#include "lashid/operator_fit/output_dynamics.hpp"
#include "lashid/sim/scenario.hpp"

namespace {

using namespace lashid::sim;
using lashid::test::Contains;
using lashid::test::error_of;

const std::string kHeader = "t_s,x_in,F_kip,v_in_per_s\n";

// ------------------------------------------------------------------------------------------------------ loader

TEST(DamperData, ReadsColumnsByNameAndIgnoresOthers) {
  const auto r = parse_damper_csv("F_kip,extra,t_s,x_in\r\n1.5,abc,0,0.25\r\n\r\n-2,,0.5,-1e-3\r\n", "a.csv");
  EXPECT_EQ(r.source, "a.csv");
  EXPECT_EQ(r.t, (std::vector<double>{0, 0.5}));
  EXPECT_EQ(r.v, (std::vector<double>{0.25, -1e-3}));
  EXPECT_EQ(r.u, (std::vector<double>{1.5, -2}));
}

TEST(DamperData, MissingColumnNamesTheColumnAndListsTheHeader) {
  const std::string e = error_of([] { parse_damper_csv("t_s,x_in,force\n0,0,0\n", "a.csv"); });
  EXPECT_TRUE(Contains(e, "a.csv:1: no column 'F_kip'"));
  EXPECT_TRUE(Contains(e, "'force'"));
}

TEST(DamperData, NanNamesLineAndColumn) {
  const std::string e = error_of([] { parse_damper_csv(kHeader + "0,0,0,0\n0.1,nan,0,0\n", "a.csv"); });
  EXPECT_TRUE(Contains(e, "a.csv:3: column 'x_in': 'nan' is not finite"));
  const std::string inf = error_of([] { parse_damper_csv(kHeader + "0,0,-inf,0\n", "a.csv"); });
  EXPECT_TRUE(Contains(inf, "a.csv:2: column 'F_kip'"));
}

TEST(DamperData, NonNumericNamesLineAndColumn) {
  const std::string e = error_of([] { parse_damper_csv(kHeader + "0,0,0,0\n0.1,0,1.2.3,0\n", "a.csv"); });
  EXPECT_TRUE(Contains(e, "a.csv:3: column 'F_kip': '1.2.3' is not a number"));
  const std::string empty_field = error_of([] { parse_damper_csv(kHeader + "0,,0,0\n", "a.csv"); });
  EXPECT_TRUE(Contains(empty_field, "a.csv:2: column 'x_in': '' is not a number"));
}

TEST(DamperData, RaggedRowNamesLineAndCounts) {
  const std::string e = error_of([] { parse_damper_csv(kHeader + "0,0,0,0\n0.1,0,0\n", "a.csv"); });
  EXPECT_TRUE(Contains(e, "a.csv:3: 3 fields, but the header has 4"));
}

TEST(DamperData, UnsortedOrRepeatedTimeNamesLine) {
  const std::string e = error_of([] { parse_damper_csv(kHeader + "0,0,0,0\n0.2,0,0,0\n0.1,0,0,0\n", "a.csv"); });
  EXPECT_TRUE(Contains(e, "a.csv:4: column 't_s': 0.1 does not increase (previous row: 0.2)"));
  const std::string repeated = error_of([] { parse_damper_csv(kHeader + "0,0,0,0\n0,0,0,0\n", "a.csv"); });
  EXPECT_TRUE(Contains(repeated, "a.csv:3:"));
}

TEST(DamperData, EmptyFileAndNoRows) {
  EXPECT_TRUE(Contains(error_of([] { parse_damper_csv("", "a.csv"); }), "a.csv: empty file"));
  EXPECT_TRUE(Contains(error_of([] { parse_damper_csv(kHeader, "a.csv"); }), "a.csv: no data rows"));
  EXPECT_TRUE(Contains(error_of([] { read_damper_csv("/nonexistent/b.csv"); }), "/nonexistent/b.csv"));
}

TEST(DamperData, DecimateTakesBlockMeans) {
  const auto r = parse_damper_csv(kHeader + "0,1,2,0\n1,3,4,0\n2,5,6,0\n3,7,8,0\n4,9,9,0\n", "a.csv");
  const auto d = decimate(r, 2);
  EXPECT_EQ(d.t, (std::vector<double>{0.5, 2.5}));
  EXPECT_EQ(d.v, (std::vector<double>{2, 6}));
  EXPECT_EQ(d.u, (std::vector<double>{3, 7}));
  EXPECT_THROW(decimate(r, 0), std::invalid_argument);
  EXPECT_THROW(decimate(r, 6), std::invalid_argument);
}

// ------------------------------------------------------------------------------------------ synthetic fits

// A sine whose amplitude grows from 0.2 to 1 (like the damper's char_ tests), `n` samples.
std::vector<double> growing_sine(std::size_t n, double cycles) {
  std::vector<double> v(n);
  for (std::size_t t = 0; t < n; ++t) {
    const double s = static_cast<double>(t) / static_cast<double>(n - 1);
    v[t] = (0.2 + 0.8 * s) * std::sin(2 * std::numbers::pi * cycles * s);
  }
  return v;
}

TEST(OperatorFit, MotionDirectionIgnoresFlickerInsideTheDeadband) {
  const std::vector<double> v{0, 0.01, 0.02, 0.019, 0.03, 0.04, 0.02, 0.0, 0.001, -0.01};
  EXPECT_EQ(motion_direction(v, 0.005), (std::vector<int>{1, 1, 1, 1, 1, 1, -1, -1, -1, -1}));
  EXPECT_EQ(reversal_indices(v, 0.005), (std::vector<std::size_t>{5}));
}

TEST(OperatorFit, SwitchBordersAreRecoveredFromSyntheticData) {
  const auto C_a = [](double v) { return 1.0 + 0.5 * v; };
  const auto C_d = [](double v) { return -1.0 + v * v; };
  DamperRecord rec;
  rec.source = "synthetic";
  rec.v = growing_sine(20000, 10);
  SwitchOperator truth(Border::from_function(C_a, -1, 1), Border::from_function(C_d, -1, 1));
  rec.u = simulate_operator(truth, rec.v, C_d(0.0));
  rec.t.resize(rec.v.size());
  OperatorFitOptions options;
  options.points = 21;
  options.deadband = 1e-4;
  const NominalFit fit = fit_nominal({rec}, options);
  EXPECT_EQ(fit.chosen, "switch");
  EXPECT_GT(fit.fit_train_switch, 97.0);
  // Each node is the median of its bin of half-width h = 0.05: within |C'| h of the closed form.
  for (double v = -0.9; v <= 0.9; v += 0.1) {
    EXPECT_NEAR(fit.ascending(v), C_a(v), 0.5 * 0.05 + 1e-6) << v;
    EXPECT_NEAR(fit.descending(v), C_d(v), 2.0 * 0.05 + 1e-6) << v;
  }
}

// G of a friction element with a gap: plateaus -2 / +2.5 at |e| >= r = 0.16, zero force for |e| < 0.06, linear in
// between.
double gap_curve(double e) {
  if (e >= 0.16) return 2.5;
  if (e <= -0.16) return -2.0;
  if (e > 0.06) return 2.5 * (e - 0.06) / 0.1;
  if (e < -0.06) return -2.0 * (-e - 0.06) / 0.1;
  return 0.0;
}

FrictionGapOperator synthetic_gap(double k) {
  std::vector<std::pair<double, double>> table;
  for (double e : {-0.16, -0.06, 0.06, 0.16}) table.emplace_back(e, gap_curve(e));
  return FrictionGapOperator(Border::from_table(table), k);
}

TEST(FrictionGap, FollowsThePlayAndTheCurve) {
  FrictionGapOperator op = synthetic_gap(0.5);
  op.reset(0.0, 0.0);  // in the gap: e = 0, z = 0
  constexpr double kTol = 1e-12;
  EXPECT_NEAR(op.step(0.05), 0.025, kTol);                 // e = 0.05, still slack: only k v
  EXPECT_NEAR(op.step(0.11), 1.25 + 0.055, kTol);          // e = 0.11, engaged
  EXPECT_NEAR(op.step(1.0), 2.5 + 0.5, kTol);              // sliding up: z = 0.84
  EXPECT_NEAR(op.slider(), 1.0 - 0.16, kTol);
  EXPECT_NEAR(op.step(0.9), gap_curve(0.06) + 0.45, kTol);  // reversal: e = 0.06, force dropped to the gap
  auto copy = op.clone();
  EXPECT_NEAR(op.step(0.5), -2.0 + 0.25, kTol);            // sliding down: z = 0.66
  EXPECT_NEAR(copy->step(0.5), -2.0 + 0.25, kTol);         // the clone had the same state
  EXPECT_EQ(op.name(), "friction_gap");
  EXPECT_THROW(op.step(std::nan("")), std::invalid_argument);
  op.reset(0.3, 2.5 + 0.15);                               // on the upper plateau: e = 0.16
  EXPECT_NEAR(op.slider(), 0.3 - 0.16, kTol);
  std::vector<std::pair<double, double>> positive{{0.1, 0.0}, {0.2, 1.0}};
  EXPECT_THROW(FrictionGapOperator(Border::from_table(positive), 0.0), std::invalid_argument);
}

TEST(FrictionGap, FitRecoversPlayWidthAndCurve) {
  DamperRecord rec;
  rec.source = "synthetic";
  rec.v = growing_sine(20000, 10);
  const FrictionGapOperator truth = synthetic_gap(0.0);
  FrictionGapOperator start = truth;
  start.reset(rec.v[0], 0.0);
  rec.u = simulate_operator(start, rec.v, 0.0);
  rec.t.resize(rec.v.size());
  OperatorFitOptions options;
  options.points = 33;  // nodes every 0.01 on [-0.16, 0.16]: the kinks at +-0.06 are nodes
  options.half_widths = {0.10, 0.12, 0.14, 0.16, 0.18, 0.20};
  options.parallel_stiffness = false;
  const ExtendedFit fit = fit_extended({rec}, options);
  EXPECT_DOUBLE_EQ(fit.half_width, 0.16);
  EXPECT_GT(fit.fit_train, 99.0);
  const auto model = fit.make();
  for (double e = -0.16; e <= 0.1601; e += 0.02) EXPECT_NEAR(model->curve()(e), gap_curve(e), 0.1) << e;
}

TEST(LoopAnalysis, LocatesAnErrorThatFollowsReversals) {
  DamperRecord rec;
  rec.v = growing_sine(8000, 8);
  rec.t.resize(rec.v.size());
  for (std::size_t t = 0; t < rec.t.size(); ++t) rec.t[t] = 0.001 * static_cast<double>(t);
  FrictionGapOperator truth = synthetic_gap(0.0);
  truth.reset(rec.v[0], 0.0);
  rec.u = simulate_operator(truth, rec.v, 0.0);
  // The paper's switch with the plateaus as borders: jumps at reversals where the measurement crosses the gap.
  std::vector<std::pair<double, double>> up{{-1, 2.5}, {1, 2.5}}, down{{-1, -2.0}, {1, -2.0}};
  const SwitchOperator nominal(Border::from_table(up), Border::from_table(down));
  const auto u_sim = simulate_operator(nominal, rec.v, 0.0);
  LoopPhaseOptions options;
  options.deadband = 1e-4;
  options.reversal_window = 0.12;
  options.engagement_window = 0.32;
  options.stick_speed = 0.0;
  const LoopAnalysis a = analyse_loop(rec, u_sim, options);
  EXPECT_GE(a.reversals, 14U);
  ASSERT_EQ(a.phases.size(), kLoopPhaseNames.size());
  EXPECT_EQ(a.phase(LoopPhase::kReversal).phase, "reversal");
  EXPECT_EQ(a.phase(LoopPhase::kSliding).phase, "sliding");
  EXPECT_EQ(a.phase(LoopPhase::kStick).phase, "stick");
  EXPECT_GT(a.phase(LoopPhase::kReversal).share_of_squared_error +
                a.phase(LoopPhase::kEngagement).share_of_squared_error,
            0.99);
  EXPECT_NEAR(a.phase(LoopPhase::kSliding).rms, 0.0, 1e-9);
  // Over 0.12 of travel from a plateau the force falls to the gap: 2.5 / 0.12 (top) or 2 / 0.12 (bottom).
  EXPECT_GE(a.measured_reversal_slope, 2.0 / 0.12 - 0.5);
  EXPECT_LE(a.measured_reversal_slope, 2.5 / 0.12 + 0.5);
  EXPECT_NEAR(a.plateau, 2.5, 1e-9);
  // |u| < 0.25 for e in [-0.06, 0.06] and 0.01 (top) + 0.0125 (bottom) beyond: 0.1425 per half-cycle.
  EXPECT_NEAR(a.measured_gap, 0.1425, 0.01);
  EXPECT_LT(a.simulated_gap, 0.01);
}

TEST(OperatorFit, FitToRecordScoresADivergedSimulationAsMinusInfinity) {
  DamperRecord rec;
  rec.source = "r.csv";
  rec.u = {0.0, 2.0};
  EXPECT_DOUBLE_EQ(fit_to_record(rec, std::vector<double>{0.5, 1.5}), 50.0);  // stats::fit_percent
  EXPECT_EQ(fit_to_record(rec, std::vector<double>{0.5, std::nan("")}), -std::numeric_limits<double>::infinity());
  EXPECT_EQ(fit_to_record(rec, std::vector<double>{std::numeric_limits<double>::infinity(), 1.0}),
            -std::numeric_limits<double>::infinity());
  // A constant measured force has no fit (the norm about its mean is 0): an error naming the file.
  rec.u = {1.0, 1.0};
  try {
    fit_to_record(rec, std::vector<double>{1.0, 1.0});
    ADD_FAILURE() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_TRUE(Contains(e.what(), "r.csv: cannot score a simulation")) << e.what();
  }
}

// ------------------------------------------------------------------------------------------ damper causes

// A loop analysis with the given shares of the squared error in the reversal and engagement phases.
LoopAnalysis analysis(double reversal_share, double engagement_share) {
  LoopAnalysis a;
  for (const char* name : kLoopPhaseNames) a.phases.push_back(PhaseError{name, 100, 0.0, 0.0});
  a.phases[static_cast<std::size_t>(LoopPhase::kReversal)].share_of_squared_error = reversal_share;
  a.phases[static_cast<std::size_t>(LoopPhase::kEngagement)].share_of_squared_error = engagement_share;
  a.plateau = 2.0;
  return a;
}

std::vector<std::string> names(const std::vector<DamperCause>& causes) {
  std::vector<std::string> out;
  for (const auto& c : causes) out.push_back(c.name);
  return out;
}

TEST(DamperCauses, ErrorAfterReversalsOnAverage) {
  const ExtendedFit fit;  // k = 0
  // Mean share (0.4 + 0.1 + 0.3 + 0.1) / 2 = 0.45: not more than half.
  EXPECT_TRUE(damper_causes({analysis(0.4, 0.1), analysis(0.3, 0.1)}, {}, fit, 3.0).empty());
  // (0.5 + 0.1 + 0.4 + 0.1) / 2 = 0.55.
  const auto causes = damper_causes({analysis(0.5, 0.1), analysis(0.4, 0.1)}, {}, fit, 3.0);
  ASSERT_EQ(names(causes), std::vector<std::string>{"finite_stiffness_at_reversal"});
  EXPECT_TRUE(causes[0].in_extended_model);
  EXPECT_TRUE(Contains(causes[0].evidence, "on average 45 % (reversal) + 10 % (engagement)"));
  DamperCauseOptions strict;
  strict.reversal_error_share = 0.6;
  EXPECT_TRUE(damper_causes({analysis(0.5, 0.1), analysis(0.4, 0.1)}, {}, fit, 3.0, strict).empty());
}

TEST(DamperCauses, GapMustExistAndMoveFurtherThanItsWidth) {
  const ExtendedFit fit;
  LoopAnalysis a = analysis(0.0, 0.0);
  a.measured_gap = 0.14;
  a.measured_gap_centre_spread = 0.10;  // moves less than its width: could be a border's zero crossing
  EXPECT_TRUE(damper_causes({a}, {}, fit, 3.0).empty());
  a.measured_gap_centre_spread = 2.8;
  EXPECT_EQ(names(damper_causes({a}, {}, fit, 3.0)), std::vector<std::string>{"zero_force_gap_moving_with_reversal"});
  a.measured_gap = 0.01;  // below min_gap: no gap
  EXPECT_TRUE(damper_causes({a}, {}, fit, 3.0).empty());
}

TEST(DamperCauses, ParallelStiffnessCountsAboveAShareOfTheFrictionLevel) {
  ExtendedFit fit;
  fit.stiffness = 0.03;  // over a span of 3: 0.09, 4.5 % of the plateau 2
  EXPECT_TRUE(damper_causes({analysis(0.0, 0.0)}, {}, fit, 3.0).empty());
  fit.stiffness = -0.04;  // 0.12: 6 %
  const auto causes = damper_causes({analysis(0.0, 0.0)}, {}, fit, 3.0);
  ASSERT_EQ(names(causes), std::vector<std::string>{"position_dependent_friction"});
  EXPECT_TRUE(Contains(causes[0].evidence, "-0.040 per unit of v"));
  EXPECT_TRUE(Contains(causes[0].evidence, "6 % of the friction level"));
}

TEST(DamperCauses, SlidingErrorGrowingWithSpeedIsNotModelled) {
  const ExtendedFit fit;
  const auto extended = [](double peak_speed, double sliding_rms, std::size_t sliding_samples) {
    LoopAnalysis a = analysis(0.0, 0.0);
    a.peak_speed = peak_speed;
    a.phases[static_cast<std::size_t>(LoopPhase::kSliding)].rms = sliding_rms;
    a.phases[static_cast<std::size_t>(LoopPhase::kSliding)].samples = sliding_samples;
    return a;
  };
  const std::vector<LoopAnalysis> nominal{analysis(0.0, 0.0)};
  // Fastest 6.2 with RMS 0.48, slowest 0.8 with 0.21: ratio 2.3. A file without sliding does not count.
  const auto causes =
      damper_causes(nominal, {extended(6.2, 0.48, 10), extended(0.1, 0.01, 0), extended(0.8, 0.21, 10)}, fit, 3.0);
  ASSERT_EQ(names(causes), std::vector<std::string>{"rate_dependence"});
  EXPECT_FALSE(causes[0].in_extended_model);
  EXPECT_TRUE(Contains(causes[0].evidence, "0.480 at a peak speed of 6.20 per s and 0.210 at 0.80 per s"));
  EXPECT_TRUE(damper_causes(nominal, {extended(6.2, 0.30, 10), extended(0.8, 0.21, 10)}, fit, 3.0).empty());
  EXPECT_TRUE(damper_causes(nominal, {extended(6.2, 0.48, 10)}, fit, 3.0).empty());  // one file: no comparison
  EXPECT_TRUE(damper_causes({}, {extended(6.2, 0.48, 10), extended(0.8, 0.21, 10)}, fit, 3.0).empty());
}

// ------------------------------------------------------------------------------------ as a scenario actuator

TEST(FrictionGap, IsTheActuatorOfAnIdentificationScenario) {
  const Scenario s = actuator_scenario(synthetic_gap(0.0), -1.0, 1.0, 1e-4);
  ASSERT_TRUE(s.config.truth.has_value());
  const Recording rec = simulate(s, SimulationOptions{});
  for (const auto scheme : {lashid::est::Scheme::kDescending, lashid::est::Scheme::kAscending}) {
    const SchemeResult r = identify_scheme(s.config, rec, scheme, IdentifyOptions{}, "sim");
    ASSERT_EQ(r.status, lashid::est::Status::kOk);
    const bool dis = scheme == lashid::est::Scheme::kDescending;
    const auto& F = dis ? s.config.truth->F_d : s.config.truth->F_a;
    EXPECT_NEAR(r.a[0], 1.0, 0.01);
    EXPECT_NEAR(r.a[1], 0.21, 0.01);
    for (std::size_t j = 0; j < F.size(); ++j) EXPECT_NEAR(r.F[j], F[j], 0.01) << j;
  }
  // The pulse response is the plateau for every level more than 2r below v_max: the loop's gap is invisible there.
  EXPECT_NEAR(s.config.truth->F_d[0], s.config.truth->F_d[2], 1e-9);
}

// ------------------------------------------------------------------------------------------ the measured damper

DamperRecord damper(const std::string& name) {
  // Every 4th sample (block means): 256 Hz keeps the test fast under the sanitizers.
  return decimate(read_damper_csv(std::string(LASHID_DAMPER_DATA) + "/" + name), 4);
}

// Trained on one slow and one fast characterisation test, tested on other frequencies and amplitudes and on the
// earthquake record (another band tension): the friction-gap operator must beat the best paper operator by far.
TEST(DamperFit, ExtendedModelBeatsNominalOnHeldOutFiles) {
  const std::vector<DamperRecord> train{damper("char_0.25Hz30lbtension1amplitude.csv"),
                                        damper("char_1Hz30lbtension1.5amplitude.csv")};
  const OperatorFitOptions options;
  const NominalFit nominal = fit_nominal(train, options);
  const ExtendedFit extended = fit_extended(train, options);
  EXPECT_GT(extended.half_width, 0.08);  // the play holds the zero-force gap (~0.15 in wide) and the two slopes
  EXPECT_LT(extended.half_width, 0.30);
  const auto nominal_op = nominal.make();
  const auto extended_op = extended.make();
  for (const std::string name : {"char_0.5Hz30lbtension0.5amplitude.csv", "char_1Hz30lbtension1amplitude.csv",
                                 "char_0.25Hz30lbtension1.5amplitude.csv", "eq_KocaeliDBE.csv"}) {
    const DamperRecord rec = damper(name);
    const double f_nom = fit_to_record(rec, simulate_operator(*nominal_op, rec.v, rec.u.front()));
    const double f_ext = fit_to_record(rec, simulate_operator(*extended_op, rec.v, rec.u.front()));
    EXPECT_GT(f_ext, f_nom + 20.0) << name << ": nominal " << f_nom << " %, extended " << f_ext << " %";
    EXPECT_GT(f_ext, name.starts_with("eq_") ? 40.0 : 70.0) << name;
  }
}

}  // namespace
