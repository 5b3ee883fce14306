// lashid diagnose: the joint model, the hidden-effect generator, and the diagnosis on recordings with a hidden
// effect. The truth comes from the generator (drawn plant, effect and size), never from the diagnosis itself.
// Seeds 5000+ are used here; the decision thresholds were chosen on seeds 1000-1005 and 2000-2009.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <span>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "lashid/analysis/joint_model.hpp"
#include "lashid/diagnose/diagnosis.hpp"
#include "lashid/sim/hidden_effect.hpp"

namespace {

using namespace lashid::sim;

TEST(HiddenEffect, IsDeterministicAndKeepsTheEffectOutOfTheConfig) {
  const HiddenEffectCase a = generate_hidden_effect_case(Cause::kOperatorType, 7);
  const HiddenEffectCase b = generate_hidden_effect_case(Cause::kOperatorType, 7);
  EXPECT_EQ(a.recording, b.recording);
  EXPECT_FALSE(a.config.truth.has_value());
  EXPECT_NE(a.config.op, a.effect.true_operator);  // the user's belief is wrong
  for (Phase p : kAllPhases) EXPECT_TRUE(a.recording.has(p)) << to_string(p);
  EXPECT_NO_THROW(check_recording_matches(a.config, a.recording, "generated"));
  // The lag drawn is in the documented range (hidden_effect.hpp: lambda in [0.15, 0.5]).
  const HiddenEffectCase lag = generate_hidden_effect_case(Cause::kInputLag, 7);
  EXPECT_GE(lag.effect.lambda, 0.15);
  EXPECT_LE(lag.effect.lambda, 0.5);
  EXPECT_EQ(parse_cause("sensor_drift"), Cause::kSensorDrift);
  EXPECT_EQ(parse_cause("drift"), std::nullopt);
}

// Noise-free equivalence: on a plant without effect the joint fit returns the generator's A, B and borders,
// scaled as (3.11c): b K and (C - u_M) / K with K = u_M - u_m.
TEST(JointModel, RecoversTheGeneratedPlant) {
  for (std::uint64_t seed : {5100U, 5101U, 5102U}) {
    const HiddenEffectCase c = generate_hidden_effect_case(Cause::kNone, seed);
    ModelStructure s;
    s.op = c.config.op;
    const JointModel m = fit_joint_model(c.config, flatten(c.recording), s);
    ASSERT_TRUE(m.ok) << m.failure;
    const auto& e = c.effect;
    const double u_M = e.border_ascending.back(), K = u_M - e.border_descending.front();
    for (std::size_t i = 0; i < c.model.a.size(); ++i) {
      EXPECT_NEAR(m.a[i], c.model.a[i], 0.02) << "seed " << seed << " a" << i + 1;
      EXPECT_NEAR(m.b[i], c.model.b[i] * K, 0.02 * std::abs(c.model.b[0] * K)) << "seed " << seed << " b" << i + 1;
    }
    for (std::size_t k = 0; k < e.border_v.size(); ++k) {
      EXPECT_NEAR(m.descending_u[k], (e.border_descending[k] - u_M) / K, 0.02) << "seed " << seed << " C_d " << k;
      EXPECT_NEAR(m.ascending_u[k], (e.border_ascending[k] - u_M) / K, 0.02) << "seed " << seed << " C_a " << k;
    }
    EXPECT_NEAR(m.residual_variance, c.noise_variance, 0.1 * c.noise_variance) << "seed " << seed;
  }
}

// A file may hold its phases in any order (data-format.md): with val before step_a, the rows just after val would
// regress on val's outputs. No row of the fit may have a val sample among its n lags.
TEST(JointModel, NoRowRegressesOnValWhereverValLies) {
  const HiddenEffectCase c = generate_hidden_effect_case(Cause::kNone, 5103);
  Recording reordered;
  for (const Phase p : {Phase::kStepD, Phase::kDis, Phase::kVal, Phase::kStepA, Phase::kAis}) {
    for (const Sample& x : c.recording.phase(p)) reordered.append(p, x.v, x.y);
  }
  const FlatRecording data = flatten(reordered);
  ModelStructure s;
  s.op = c.config.op;
  const JointModel m = fit_joint_model(c.config, data, s);
  ASSERT_TRUE(m.ok) << m.failure;
  std::size_t after_val = 0;
  for (const std::size_t t : m.residual_t) {
    for (int i = 0; i <= m.n; ++i) EXPECT_TRUE(data.is_identification(t - static_cast<std::size_t>(i))) << t << " " << i;
    if (data.phase[t] == Phase::kStepA && !data.is_identification(t - static_cast<std::size_t>(m.n) - 1)) ++after_val;
  }
  EXPECT_EQ(after_val, 1U) << "the first row after val is the n-th sample of step_a";
}

TEST(HiddenEffect, CurvedBordersKeepThePlantAndChangeOnlyTheBorders) {
  const std::array<Cause, 1> drift{Cause::kSensorDrift};
  HiddenEffectOptions curved;
  curved.borders = BorderShape::kCurved;
  const HiddenEffectCase a = generate_hidden_effect_case(drift, 5300, {});
  const HiddenEffectCase b = generate_hidden_effect_case(drift, 5300, curved);
  EXPECT_EQ(a.config.V_d, b.config.V_d);
  EXPECT_EQ(a.model.a, b.model.a);
  EXPECT_EQ(a.effect.true_operator, b.effect.true_operator);
  EXPECT_NE(a.recording, b.recording);
  EXPECT_NE(a.effect.border_descending, b.effect.border_descending);
  // The true model's val output: the measured val minus the equation error only, so it fits the measurement
  // almost perfectly (the error is 0.3-1 % of the border rise).
  for (const HiddenEffectCase* c : {&a, &b}) {
    std::vector<double> measured;
    for (const Sample& s : c->recording.phase(Phase::kVal)) measured.push_back(s.y);
    ASSERT_EQ(measured.size(), c->val_true_output.size());
    double error = 0, spread = 0, mean = 0;
    for (double y : measured) mean += y / static_cast<double>(measured.size());
    for (std::size_t k = 0; k < measured.size(); ++k) {
      error += std::pow(measured[k] - c->val_true_output[k], 2);
      spread += std::pow(measured[k] - mean, 2);
    }
    EXPECT_LT(std::sqrt(error / spread), 0.05);
  }
}

TEST(HiddenEffect, HidesPairsAndRejectsBadLists) {
  const std::array<Cause, 2> pair{Cause::kInputLag, Cause::kSensorDrift};
  const HiddenEffectCase c = generate_hidden_effect_case(pair, 5301, {});
  EXPECT_EQ(c.effect.causes, (std::vector<Cause>{Cause::kInputLag, Cause::kSensorDrift}));
  EXPECT_EQ(c.effect.cause, Cause::kInputLag);
  EXPECT_GE(c.effect.lambda, 0.15);
  EXPECT_LE(c.effect.lambda, 0.5);
  EXPECT_NE(c.effect.drift_total, 0.0);
  EXPECT_FALSE(c.config.truth.has_value());
  const std::array<Cause, 2> repeated{Cause::kDeadTime, Cause::kDeadTime};
  const std::array<Cause, 2> none_and_other{Cause::kNone, Cause::kDeadTime};
  EXPECT_THROW((void)generate_hidden_effect_case(repeated, 1, {}), std::invalid_argument);
  EXPECT_THROW((void)generate_hidden_effect_case(none_and_other, 1, {}), std::invalid_argument);
  EXPECT_THROW((void)generate_hidden_effect_case(std::span<const Cause>{}, 1, {}), std::invalid_argument);
}

// With the true lambda and borders linear between the levels, the points the finer tables add between the
// abscissas must lie on the generator's straight segments (scaled as (3.11c)). A switch: behind an input lag it
// moves along its borders wherever the input goes, so the data reach every point (a backlash holds over parts of
// its borders, which these experiments then cannot identify; docs/diagnose.md).
TEST(JointModel, FinerBorderTablesFollowTheTrueBordersBetweenTheLevels) {
  const HiddenEffectCase c = generate_hidden_effect_case(Cause::kInputLag, 5106);
  ASSERT_EQ(c.effect.true_operator, OperatorKind::kSwitch);
  ModelStructure s;
  s.op = c.config.op;
  s.input_lag = c.effect.lambda;
  s.border_segments = 3;
  const JointModel m = fit_joint_model(c.config, flatten(c.recording), s);
  ASSERT_TRUE(m.ok) << m.failure;
  const auto& e = c.effect;
  ASSERT_EQ(m.descending_v.size(), 3 * (e.border_v.size() - 1) + 1);
  const double u_M = e.border_ascending.back(), K = u_M - e.border_descending.front();
  const auto true_border = [&](const std::vector<double>& values, double v) {
    std::size_t k = 1;
    while (k + 1 < e.border_v.size() && e.border_v[k] < v) ++k;
    const double f = (v - e.border_v[k - 1]) / (e.border_v[k] - e.border_v[k - 1]);
    return ((1 - f) * values[k - 1] + f * values[k] - u_M) / K;
  };
  for (std::size_t k = 0; k < m.descending_v.size(); ++k) {
    EXPECT_NEAR(m.descending_u[k], true_border(e.border_descending, m.descending_v[k]), 0.03) << "C_d " << k;
    EXPECT_NEAR(m.ascending_u[k], true_border(e.border_ascending, m.ascending_v[k]), 0.03) << "C_a " << k;
  }
}

TEST(Diagnose, RejectsRecordingsItCannotDiagnose) {
  const HiddenEffectCase c = generate_hidden_effect_case(Cause::kNone, 5200);
  Recording no_val;
  for (Phase p : c.recording.order()) {
    if (p == Phase::kVal) continue;
    for (const Sample& s : c.recording.phase(p)) no_val.append(p, s.v, s.y);
  }
  try {
    (void)diagnose(c.config, no_val, "rec.csv");
    FAIL() << "no exception";
  } catch (const DataError& e) {
    EXPECT_NE(std::string(e.what()).find("rec.csv: diagnose needs all five phases; 'val' is missing"),
              std::string::npos)
        << e.what();
  }
  Recording short_val = no_val;
  for (int t = 0; t < 50; ++t) short_val.append(Phase::kVal, c.config.v_min, 0.0);
  try {
    (void)diagnose(c.config, short_val, "rec.csv");
    FAIL() << "no exception";
  } catch (const DataError& e) {
    EXPECT_NE(std::string(e.what()).find("phase 'val' has 50 samples"), std::string::npos) << e.what();
  }
  ExperimentConfig other = c.config;
  other.V_d[1] += 0.01;  // the recording's pulses are no longer on the design
  EXPECT_THROW((void)diagnose(other, c.recording, "rec.csv"), DataError);
}

}  // namespace


namespace {

// The first sample of the val phase (the last phase of the recording).
std::size_t first_val_sample(const FlatRecording& data) {
  std::size_t val = 0;
  while (val < data.size() && data.is_identification(val)) ++val;
  return val;
}

// The RMS of x - truth over the samples of truth (x at least as long); NaN where x diverged.
double rms_difference(std::span<const double> x, std::span<const double> truth) {
  double sum = 0;
  for (std::size_t t = 0; t < truth.size(); ++t) sum += std::pow(x[t] - truth[t], 2);
  return std::sqrt(sum / static_cast<double>(truth.size()));
}

}  // namespace

// Under white sensor noise (the colored_noise effect, SNR 20-30 dB) output error is the consistent estimator and
// instrumental variables a poor one for n = 3: the refit by output error (ModelStructure::output_error) must
// simulate val closer to the plant's noise-free output (the generator's truth) than the IV fit it starts from,
// on every seed, and its border points must be closer to the true ones.
TEST(JointModel, OutputErrorSimulatesCloserToTheTruthUnderSensorNoise) {
  double ratio_sum = 0;
  int seeds = 0;
  for (std::uint64_t seed = 5200; seed < 5212; ++seed, ++seeds) {
    const HiddenEffectCase c = generate_hidden_effect_case(Cause::kColoredNoise, seed);
    const FlatRecording data = flatten(c.recording);
    ModelStructure s;
    s.op = c.config.op;
    s.instrumental = true;
    const JointModel iv = fit_joint_model(c.config, data, s);
    s.output_error = true;
    const JointModel oe = fit_joint_model(c.config, data, s);
    ASSERT_TRUE(iv.ok && oe.ok) << "seed " << seed;
    const std::size_t val = first_val_sample(data);
    ASSERT_EQ(data.size() - val, c.val_true_output.size());
    const auto rms_to_truth = [&](const JointModel& m) {
      return rms_difference(simulate_segment(m, data, val, data.size()), c.val_true_output);
    };
    const double rms_iv = rms_to_truth(iv), rms_oe = rms_to_truth(oe);
    EXPECT_LT(rms_oe, rms_iv) << "seed " << seed << " n " << c.config.n;
    ratio_sum += rms_oe / rms_iv;
    const auto& e = c.effect;
    const double u_M = e.border_ascending.back(), K = u_M - e.border_descending.front();
    double border_iv = 0, border_oe = 0;
    for (std::size_t k = 0; k < e.border_v.size(); ++k) {
      const double d = (e.border_descending[k] - u_M) / K, a = (e.border_ascending[k] - u_M) / K;
      border_iv = std::max({border_iv, std::abs(iv.descending_u[k] - d), std::abs(iv.ascending_u[k] - a)});
      border_oe = std::max({border_oe, std::abs(oe.descending_u[k] - d), std::abs(oe.ascending_u[k] - a)});
    }
    EXPECT_LT(border_oe, border_iv) << "seed " << seed;
  }
  EXPECT_LT(ratio_sum / seeds, 0.8);
}

// Session 33: output error is a local search, and an IV fit of an order-3 plant can be unstable, its simulation
// diverging; output error cannot refine such a start. Started also from the least-squares model and from the IV model
// with A's unstable roots reflected (ModelStructure::output_error_restarts), the colored_noise structure of tuning
// seeds 1062 and 1224 (curved borders, n = 3), whose fits had simulated val to infinity, simulates the plant's
// noise-free val output (the generator's truth) closer than the sensor noise lies from it.
TEST(JointModel, OutputErrorFromMoreStartsReachesTheTruthWhereTheIvFitDiverges) {
  HiddenEffectOptions curved;
  curved.borders = BorderShape::kCurved;
  const std::array<Cause, 1> noise{Cause::kColoredNoise};
  for (std::uint64_t seed : {1062U, 1224U}) {
    const HiddenEffectCase c = generate_hidden_effect_case(noise, seed, curved);
    const FlatRecording data = flatten(c.recording);
    const std::size_t val = first_val_sample(data);
    ASSERT_EQ(data.size() - val, c.val_true_output.size());
    const auto rms_to_truth = [&](std::span<const double> x) { return rms_difference(x, c.val_true_output); };
    const double noise_rms = rms_to_truth(std::span<const double>(data.y).subspan(val));
    ModelStructure s;
    s.op = c.config.op;
    s.instrumental = true;
    s.output_error = true;
    s.output_error_restarts = false;
    const JointModel from_iv = fit_joint_model(c.config, data, s);
    s.output_error_restarts = true;
    const JointModel restarted = fit_joint_model(c.config, data, s);
    ASSERT_TRUE(from_iv.ok && restarted.ok) << "seed " << seed;
    const double rms_iv = rms_to_truth(simulate_segment(from_iv, data, val, data.size()));
    const double rms_restarted = rms_to_truth(simulate_segment(restarted, data, val, data.size()));
    EXPECT_FALSE(std::isfinite(rms_iv)) << "seed " << seed;  // from the IV model alone: diverges
    EXPECT_TRUE(restarted.structure.output_error) << "seed " << seed;
    EXPECT_LT(rms_restarted, noise_rms) << "seed " << seed;
  }
}

// A fit in the report's words: the digits where they mean something, words where the simulation ran away (a diverging
// val simulation used to print an 80-digit percentage).
TEST(DiagnosisReport, AFitThatRunsAwayIsSaidInWordsNotDigits) {
  EXPECT_EQ(lashid::sim::describe_fit(87.26), "87.3 %");
  EXPECT_EQ(lashid::sim::describe_fit(-999.0), "-999.0 %");
  EXPECT_EQ(lashid::sim::describe_fit(-6.2e80), "below -999 % (its simulation runs away)");
  EXPECT_EQ(lashid::sim::describe_fit(-std::numeric_limits<double>::infinity()), "none (its simulation diverges)");
  EXPECT_EQ(lashid::sim::describe_fit(std::numeric_limits<double>::quiet_NaN()), "none (its simulation diverges)");
}
