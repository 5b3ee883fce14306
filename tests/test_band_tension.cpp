// The friction-gap operator per band tension (docs/friction-damper.md): the tension of a file from its name or an
// override, and the fit on synthetic records from known operators at two tensions, whose plateaus scale with the
// tension by known amounts.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "lashid/operator_fit/band_tension.hpp"

namespace {

using namespace lashid::sim;

// ------------------------------------------------------------------------------------------- tension of a file

TEST(BandTension, IsReadFromTheFileName) {
  EXPECT_EQ(tension_from_file_name("tests/data/char_0.5Hz36lbtension1amplitude.csv"), 36.0);
  EXPECT_EQ(tension_from_file_name("char_2Hz30lbtension0.5amplitude.csv"), 30.0);
  EXPECT_EQ(tension_from_file_name("x_12.5lbtension.csv"), 12.5);
  EXPECT_EQ(tension_from_file_name("eq_KocaeliDBE.csv"), std::nullopt);
  EXPECT_EQ(tension_from_file_name("run36lbtension/eq_KocaeliDBE.csv"), std::nullopt);  // the base name only
  EXPECT_EQ(tension_from_file_name("lbtension.csv"), std::nullopt);                     // no number
}

TEST(BandTension, OverrideIsFileEqualsPounds) {
  const TensionOverride o = parse_tension_override("eq_KocaeliDBE.csv=36");
  EXPECT_EQ(o.file, "eq_KocaeliDBE.csv");
  EXPECT_EQ(o.tension_lb, 36.0);
  const std::vector<TensionOverride> overrides{o, parse_tension_override("d/char_1Hz30lbtension1amplitude.csv=31")};
  EXPECT_EQ(file_tension("some/dir/eq_KocaeliDBE.csv", overrides), 36.0);        // by base name
  EXPECT_EQ(file_tension("d/char_1Hz30lbtension1amplitude.csv", overrides), 31.0);  // beats the name
  EXPECT_EQ(file_tension("char_1Hz30lbtension1amplitude.csv", overrides), 30.0);    // other path: its name
  EXPECT_EQ(file_tension("eq_ImperialValleyDBE.csv", overrides), std::nullopt);
  for (const char* bad : {"eq_KocaeliDBE.csv", "=36", "eq.csv=", "eq.csv=abc", "eq.csv=-1", "eq.csv=36lb"}) {
    try {
      parse_tension_override(bad);
      ADD_FAILURE() << bad << " was accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(std::string("'") + bad + "'"), std::string::npos) << e.what();
    }
  }
}

// ------------------------------------------------------------------------------- fit on known synthetic tensions

// G with a zero-force gap on [-0.06, 0.06], linear engagement to the plateaus `up` at e >= 0.16 and `down` at
// e <= -0.16.
FrictionGapOperator known_operator(double up, double down) {
  std::vector<std::pair<double, double>> table{{-0.16, down}, {-0.06, 0.0}, {0.06, 0.0}, {0.16, up}};
  return FrictionGapOperator(Border::from_table(table), 0.0);
}

// A sine whose amplitude grows from 0.3 to 1.0 over `cycles` cycles, run through `op` from rest.
DamperRecord record_of(const FrictionGapOperator& op, double cycles, const std::string& name) {
  DamperRecord rec;
  rec.source = name;
  const std::size_t n = 12000;
  for (std::size_t t = 0; t < n; ++t) {
    const double s = static_cast<double>(t) / static_cast<double>(n - 1);
    rec.t.push_back(s);
    rec.v.push_back((0.3 + 0.7 * s) * std::sin(2 * std::numbers::pi * cycles * s));
  }
  FrictionGapOperator start = op;
  start.reset(0.0, 0.0);
  rec.u = simulate_operator(start, rec.v, 0.0);
  return rec;
}

// Truth: at 30 lb the plateaus are +2.5 / -2.0; at 36 lb +3.0 / -3.6, i.e. the upper plateau grows by 0.5 / 6 lb =
// 0.0833 per lb and the lower by -1.6 / 6 lb = -0.2667 per lb. The plateaus are linear in tension, so at 33 lb
// they are +2.75 / -2.8.
OperatorFitOptions known_options() {
  OperatorFitOptions options;
  options.points = 33;  // nodes every 0.01 on [-0.16, 0.16]: the kinks at +-0.06 are nodes
  options.half_widths = {0.12, 0.14, 0.16, 0.18, 0.20};
  options.parallel_stiffness = false;
  return options;
}

TEST(BandTension, FitGivesBackTheKnownScaleOfThePlateaus) {
  const std::vector<DamperRecord> train{record_of(known_operator(2.5, -2.0), 8, "a30lbtension.csv"),
                                        record_of(known_operator(3.0, -3.6), 11, "b36lbtension.csv"),
                                        record_of(known_operator(2.5, -2.0), 5, "c30lbtension.csv")};
  const std::vector<double> tensions{30, 36, 30};
  const TensionFrictionFit fit = fit_extended_by_tension(train, tensions, known_options());
  ASSERT_EQ(fit.tensions.size(), 2U);
  EXPECT_DOUBLE_EQ(fit.tensions[0].half_width, 0.16);
  EXPECT_DOUBLE_EQ(fit.tensions[1].half_width, 0.16);
  EXPECT_EQ(fit.tensions[0].tension_lb, 30.0);
  EXPECT_EQ(fit.tensions[0].files, 2U);
  EXPECT_EQ(fit.tensions[1].tension_lb, 36.0);
  EXPECT_NEAR(fit.tensions[0].curve.back().second, 2.5, 1e-9);
  EXPECT_NEAR(fit.tensions[0].curve.front().second, -2.0, 1e-9);
  EXPECT_NEAR(fit.tensions[1].curve.back().second, 3.0, 1e-9);
  EXPECT_NEAR(fit.tensions[1].curve.front().second, -3.6, 1e-9);
  EXPECT_NEAR(fit.plateau_slope(true), 0.5 / 6, 1e-9);
  EXPECT_NEAR(fit.plateau_slope(false), -1.6 / 6, 1e-9);
  EXPECT_GT(fit.fit_train, 99.0);
  // A held-out record at 33 lb, never trained on, from the truth's linear law: the model at 33 lb reproduces it.
  const DamperRecord held_out = record_of(known_operator(2.75, -2.8), 7, "held_out");
  EXPECT_FALSE(fit.extrapolates(33));
  const auto model = fit.make(33);
  EXPECT_NEAR(model->curve()(0.16), 2.75, 1e-9);
  EXPECT_NEAR(model->curve()(-0.16), -2.8, 1e-9);
  EXPECT_GT(fit_to_record(held_out, simulate_operator(*model, held_out.v, 0.0)), 99.0);
  // Beyond the training tensions the law is extrapolated, and said so: at 42 lb +3.5 / -5.2.
  EXPECT_TRUE(fit.extrapolates(42));
  EXPECT_NEAR(fit.make(42)->curve()(0.16), 3.5, 1e-9);
  EXPECT_NEAR(fit.make(42)->curve()(-0.16), -5.2, 1e-9);
}

TEST(BandTension, FitRefusesOneTensionAndBadInput) {
  const std::vector<DamperRecord> train{record_of(known_operator(2.5, -2.0), 8, "a.csv"),
                                        record_of(known_operator(2.5, -2.0), 5, "b.csv")};
  try {
    fit_extended_by_tension(train, std::vector<double>{30, 30}, known_options());
    ADD_FAILURE() << "one tension was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("all are at 30 lb"), std::string::npos) << e.what();
  }
  EXPECT_THROW(fit_extended_by_tension(train, std::vector<double>{30}, known_options()), std::invalid_argument);
  try {
    fit_extended_by_tension(train, std::vector<double>{30, -1}, known_options());
    ADD_FAILURE() << "a negative tension was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("b.csv"), std::string::npos) << e.what();
  }
}

// A tension far outside the training tensions (the file name or --tension can say 1e308 lb): the extrapolated play
// width, force and stiffness are finite, or it is an error; never a table over [-inf, inf] or of NaN.
TEST(BandTension, ExtrapolationFarOutsideIsFiniteOrAClearError) {
  TensionFrictionFit fit;
  fit.tensions = {{30, 0.16, {{-0.16, -2.0}, {0.16, 2.5}}, 0, 1, {}},
                  {36, 0.18, {{-0.18, -3.6}, {0.18, 3.0}}, 0, 1, {}}};
  EXPECT_NEAR(fit.at(42).half_width, 0.20, 1e-12);  // an ordinary extrapolation
  const TensionCurve far = fit.at(1e308);
  EXPECT_TRUE(std::isfinite(far.half_width) && std::isfinite(far.stiffness));
  for (const auto& [e, g] : far.curve) EXPECT_TRUE(std::isfinite(e) && std::isfinite(g)) << e << " " << g;
  fit.tensions[1].curve = {{-0.18, -1e300}, {0.18, 1e300}};  // the force per lb overflows at 1e10 lb
  try {
    fit.at(1e10);
    ADD_FAILURE() << "an infinite force was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("cannot be extrapolated to 1e+10 lb"), std::string::npos) << e.what();
  }
}

TEST(BandTension, CauseIsNamedAboveItsShareOfTheError) {
  TensionFrictionFit fit;
  fit.tensions = {{30, 0.16, {{-0.16, -2.0}, {0.16, 2.5}}, 0, 1, {}}, {36, 0.16, {{-0.16, -3.6}, {0.16, 3.0}}, 0, 1, {}}};
  TestErrors errors{100, 89, 60, 65};  // removes 11 % of the squared error: named
  const auto named = friction_level_scales_with_band_tension(fit, errors);
  ASSERT_TRUE(named.has_value());
  EXPECT_EQ(named->name, "friction_level_scales_with_band_tension");
  EXPECT_NE(named->evidence.find("the friction force scales with band tension"), std::string::npos);
  EXPECT_NE(named->evidence.find("+0.083"), std::string::npos) << named->evidence;  // 0.5 / 6 per lb
  EXPECT_NE(named->evidence.find("-0.267"), std::string::npos) << named->evidence;  // -1.6 / 6 per lb
  errors.with_dynamics = 91;  // removes 9 %: not named
  EXPECT_FALSE(friction_level_scales_with_band_tension(fit, errors).has_value());
}

}  // namespace
