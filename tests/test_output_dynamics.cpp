// Linear dynamics after a hysteresis operator (operator -> B(q)/A(q)): the filter, its poles, ARX and output-error
// identification, the order choice and the damper's dynamics cause (docs/friction-damper.md). Every expected value
// comes from a closed form: a known continuous resonance sampled at 1024 Hz, driven by a switch's square wave.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "data_error_matchers.hpp"
#include "output_dynamics_support.hpp"
#include "lashid/operator_fit/damper_causes.hpp"
#include "lashid/operator_fit/displacement_echo.hpp"
#include "lashid/operator_fit/output_dynamics.hpp"

namespace {

using namespace lashid::sim;

using lashid::test::Contains;
using lashid::test::error_of;
using lashid::test::kPi;
using lashid::test::kRate;
using lashid::test::resonance;
using lashid::test::switch_output;
using lashid::test::through_resonance;

// ----------------------------------------------------------------------------------------- filter and poles

TEST(OutputFilter, StaticGainAndStepResponseAreTheClosedForms) {
  const OutputFilter first{{-0.5}, {0.5, 0.0}};  // y(t) = 0.5 y(t-1) + 0.5 w(t)
  EXPECT_DOUBLE_EQ(first.dc_gain(), 1.0);
  EXPECT_DOUBLE_EQ((OutputFilter{{-0.5}, {0.5, 0.25}}).dc_gain(), 1.5);  // 0.75 / 0.5
  // From rest at 0, a unit step from t = 1: y(t) = 1 - 0.5^t.
  const std::vector<double> y = first.apply(std::vector<double>{0, 1, 1, 1, 1, 1}, 0.0);
  for (std::size_t t = 0; t < y.size(); ++t) EXPECT_DOUBLE_EQ(y[t], 1 - std::pow(0.5, t)) << t;
  // At rest at the static level, a constant input keeps it.
  for (const double x : resonance(5, 0.1).apply(std::vector<double>(50, 2.0), 2.0)) EXPECT_NEAR(x, 2.0, 1e-12);
}

TEST(OutputFilter, PolesGiveBackTheContinuousFrequencyAndDamping) {
  const std::vector<FilterPole> poles = filter_poles(resonance(6.0, 0.2), kRate);
  ASSERT_EQ(poles.size(), 2U);
  for (const auto& p : poles) {
    EXPECT_NEAR(p.natural_hz, 6.0, 1e-9);
    EXPECT_NEAR(p.zeta, 0.2, 1e-9);
    EXPECT_NEAR(p.damped_hz, 6.0 * std::sqrt(1 - 0.04), 1e-9);
  }
  FilterPole dominant;
  ASSERT_TRUE(dominant_pole(poles, &dominant));
  EXPECT_GT(dominant.z.imag(), 0.0);
  // A real pole z = exp(-2 pi 10 / 1024): 10 Hz, zeta 1, no ringing.
  const auto real = filter_poles(OutputFilter{{-std::exp(-2 * kPi * 10 / kRate)}, {1, 0}}, kRate);
  ASSERT_EQ(real.size(), 1U);
  EXPECT_NEAR(real[0].natural_hz, 10.0, 1e-9);
  EXPECT_NEAR(real[0].zeta, 1.0, 1e-12);
  EXPECT_EQ(real[0].damped_hz, 0.0);
  EXPECT_FALSE(dominant_pole({}, &dominant));
  EXPECT_THROW(filter_poles(resonance(6, 0.2), 0.0), std::invalid_argument);
}

// ------------------------------------------------------------------------------------------- identification

TEST(OutputDynamics, ArxRecoversAKnownResonanceAfterASwitchExactly) {
  const std::vector<double> w = switch_output(0.7, 8.0);
  const FilterData data{w, through_resonance(w, 5.0, 0.1)};
  const OutputFilter truth = resonance(5.0, 0.1);
  const OutputFilter f = fit_arx({data}, 2);
  ASSERT_EQ(f.order(), 2);
  EXPECT_NEAR(f.a[0], truth.a[0], 1e-8);
  EXPECT_NEAR(f.a[1], truth.a[1], 1e-8);
  EXPECT_NEAR(f.b[0], truth.b[0], 1e-8);
  EXPECT_NEAR(f.b[1], 0.0, 1e-8);
  EXPECT_NEAR(f.b[2], 0.0, 1e-8);
}

TEST(OutputDynamics, OutputErrorConvergesFromAWrongStart) {
  const std::vector<double> w = switch_output(0.7, 8.0);
  const FilterData data{w, through_resonance(w, 5.0, 0.1)};
  // Start at 8 Hz with zeta 0.4: far from the truth, and a wrong static gain.
  OutputFilter start = resonance(8.0, 0.4);
  start.b[0] *= 0.8;
  const OutputFilter f = refine_output_error({data}, start, 100);
  FilterPole p;
  ASSERT_TRUE(dominant_pole(filter_poles(f, kRate), &p));
  EXPECT_NEAR(p.natural_hz, 5.0, 1e-3);
  EXPECT_NEAR(p.zeta, 0.1, 1e-4);
  EXPECT_NEAR(f.dc_gain(), 1.0, 1e-4);
}

TEST(OutputDynamics, BadInputIsAClearError) {
  const FilterData ok{{1, 2, 3, 4, 5, 6}, {1, 2, 3, 4, 5, 6}};
  EXPECT_TRUE(Contains(error_of<std::invalid_argument>([&] { fit_arx({ok}, 0); }), "order must be >= 1, got 0"));
  EXPECT_TRUE(Contains(error_of<std::invalid_argument>([] { fit_arx({}, 2); }), "no training files"));
  EXPECT_TRUE(Contains(error_of<std::invalid_argument>([] { fit_arx({FilterData{{1, 2}, {1}}}, 1); }),
                       "operator output has 2 samples, measurement 1"));
  EXPECT_TRUE(Contains(error_of<std::invalid_argument>([&] { fit_arx({ok}, 3); }), "3 equations for 7 parameters"));
  OutputDynamicsOptions bad;
  bad.min_order = 3;
  bad.max_order = 2;
  EXPECT_TRUE(Contains(error_of<std::invalid_argument>([&] { fit_output_dynamics({ok}, bad); }), "orders 3..2"));
  EXPECT_TRUE(Contains(error_of<std::invalid_argument>([&] { refine_output_error({ok}, OutputFilter{{0.5}, {1}}); }),
                       "needs n a's and n + 1 b's"));
}

// --------------------------------------------------------------------------------- what the operator misses

// At 1020 Hz a centred window of 25 samples each side holds 51 samples, exactly one period of 20 Hz: the moving
// mean removes a constant offset and leaves the sinusoid whole, so (away from the ends) the fast part is A sin, of
// energy A^2 / 2 per sample against c^2 + A^2 / 2 for the whole error.
TEST(ErrorOscillation, FindsTheFrequencyAndShareOfAFastErrorOverASlowOne) {
  constexpr double rate = 1020, amplitude = 0.3, offset = 0.4;
  std::vector<double> measured, simulated;
  for (int t = 0; t < 10 * 1020; ++t) {
    simulated.push_back(std::sin(2 * kPi * 0.5 * t / rate));  // the model's part cancels in the error
    measured.push_back(simulated.back() + offset + amplitude * std::sin(2 * kPi * 20 * t / rate));
  }
  const ErrorOscillation osc = error_oscillation(measured, simulated, rate, 50 / rate);  // 25 samples each side
  EXPECT_EQ(osc.peak_hz, 20.0);
  EXPECT_NEAR(osc.peak_amplitude, amplitude, 0.005);
  const double share = amplitude * amplitude / 2 / (offset * offset + amplitude * amplitude / 2);
  EXPECT_NEAR(osc.fast_share, share, 0.01);
  EXPECT_EQ(error_oscillation(simulated, simulated, rate).fast_share, 0.0);
  EXPECT_TRUE(Contains(error_of<std::invalid_argument>([] { error_oscillation(std::vector<double>{1, 2}, std::vector<double>{1}, 1.0); }),
                       "need equal sizes (2 vs 1)"));
}

// A chatter-like force oscillation: 14 Hz whose phase wanders (a random walk, 0.02 rad per sample), 20 s at kRate.
std::vector<double> chatter(double amplitude, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> step(0.0, 0.02);
  std::vector<double> c;
  double phase = 0;
  for (int t = 0; t < 20 * 1024; ++t) {
    phase += step(rng);
    c.push_back(amplitude * std::sin(2 * kPi * 14 * t / kRate + phase));
  }
  return c;
}

// The model misses a force oscillation c; the displacement is a slow 2 Hz sine plus (a) the rig's yield to that
// force, -c / K, (b) the same oscillation driving a slider of stiffness k (e = k v_fast), or (c) an unrelated
// oscillation of its own. Closed forms: (a) the transfer v -> e is -K (gain K, antiphase), coherence 1; (b) +k, in
// phase; (c) coherence near 0 (independent signals: bias about 1 / windows = 1 / 39).
TEST(DisplacementEcho, TellsAnEchoFromADriveAndFromNoRelation) {
  constexpr double rig = 500, slider = 34;
  const std::vector<double> c = chatter(0.3, 1), other = chatter(0.3 / rig, 2);
  std::vector<double> echoed, driven, unrelated, drive_force, zero(c.size(), 0.0);
  for (std::size_t t = 0; t < c.size(); ++t) {
    const double slow = 0.05 * std::sin(2 * kPi * 2 * static_cast<double>(t) / kRate);
    echoed.push_back(slow - c[t] / rig);
    driven.push_back(slow + other[t]);
    drive_force.push_back(slider * other[t]);
    unrelated.push_back(slow + other[t]);
  }
  const DisplacementEcho a = displacement_echo(echoed, c, zero, kRate, 14);
  EXPECT_EQ(a.windows, 39);
  EXPECT_NEAR(a.gain, rig, 0.02 * rig);
  EXPECT_GT(std::abs(a.phase_deg), 175.0);
  EXPECT_GT(a.coherence, 0.95);
  const std::string a_words = displacement_echo_words(a, slider);
  EXPECT_TRUE(Contains(a_words, "echoed by the displacement")) << a_words;
  EXPECT_TRUE(Contains(a_words, "15 times the slider's stiffness of 34.0")) << a_words;

  const DisplacementEcho b = displacement_echo(driven, drive_force, zero, kRate, 14);
  EXPECT_NEAR(b.gain, slider, 0.02 * slider);
  EXPECT_LT(std::abs(b.phase_deg), 5.0);
  EXPECT_TRUE(Contains(displacement_echo_words(b, slider), "driven by the displacement"));

  const DisplacementEcho d = displacement_echo(unrelated, c, zero, kRate, 14);
  EXPECT_LT(d.coherence, 0.2);
  EXPECT_TRUE(Contains(displacement_echo_words(d, slider), "not coherent with the displacement"));

  // Too short for two windows: nothing is claimed. Bad arguments are named.
  const std::vector<double> short_record(1000, 0.0);
  EXPECT_EQ(displacement_echo(short_record, short_record, short_record, kRate, 14).windows, 0);
  EXPECT_TRUE(Contains(displacement_echo_words(displacement_echo(short_record, short_record, short_record, kRate, 14),
                                               slider),
                       "fewer than two windows"));
  EXPECT_TRUE(Contains(error_of<std::invalid_argument>([&] { displacement_echo(echoed, c, short_record, kRate, 14); }),
                       "need equal sizes (20480, 20480, 1000)"));
  EXPECT_TRUE(Contains(error_of<std::invalid_argument>([&] { displacement_echo(echoed, c, zero, kRate, -1); }),
                       "hz and window positive"));
}

// ---------------------------------------------------------------------------------------------- cause rule

TEST(DamperCauses, DynamicsAreNamedWithTheirRingingFrequencyAndDamping) {
  const std::vector<FilterPole> poles = filter_poles(resonance(6.0, 0.2), kRate);
  // 6 sqrt(1 - 0.04) = 5.88 Hz; 50 % of the squared error removed.
  const auto cause = dynamics_after_friction_element(poles, 2, TestErrors{100, 50, 60, 75});
  ASSERT_TRUE(cause.has_value());
  EXPECT_EQ(cause->name, "dynamics_after_friction_element");
  EXPECT_TRUE(cause->in_extended_model);
  EXPECT_TRUE(Contains(cause->evidence, "rings at 5.9 Hz after reversals"));
  EXPECT_TRUE(Contains(cause->evidence, "zeta = 0.20, natural frequency 6.0 Hz"));
  EXPECT_TRUE(Contains(cause->evidence, "drops by 50.0 % (mean test fit 60.0 % -> 75.0 %)"));
  // 5 % removed is below the 10 % threshold; no poles, nothing.
  EXPECT_FALSE(dynamics_after_friction_element(poles, 2, TestErrors{100, 95, 60, 61}).has_value());
  EXPECT_FALSE(dynamics_after_friction_element({}, 2, TestErrors{100, 50, 60, 75}).has_value());
  // A real pole at 10 Hz lags by 1 / (2 pi 10) s = 15.9 ms.
  const auto lag = dynamics_after_friction_element(
      filter_poles(OutputFilter{{-std::exp(-2 * kPi * 10 / kRate)}, {1, 0}}, kRate), 1, TestErrors{100, 50, 60, 75});
  ASSERT_TRUE(lag.has_value());
  EXPECT_TRUE(Contains(lag->evidence, "real pole at 10.0 Hz (time constant 15.9 ms)"));
  // Not named, still described: a filter that adds error says so.
  EXPECT_TRUE(Contains(output_dynamics_in_words(poles, 2, TestErrors{100, 120, 60, 55}),
                       "squared error on the test files grows by 20.0 % (mean test fit 60.0 % -> 55.0 %)"));
}

}  // namespace
