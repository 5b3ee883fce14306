// lashid diagnose: the joint model, the hidden-effect generator, and the diagnosis on recordings with a hidden
// effect. The truth comes from the generator (drawn plant, effect and size), never from the diagnosis itself.
// Seeds 5000+ are used here; the decision thresholds were chosen on seeds 1000-1005 and 2000-2009.
#include <cmath>

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
  // Same seed, other cause: the same plant (only the effect differs).
  const HiddenEffectCase none = generate_hidden_effect_case(Cause::kNone, 7);
  const HiddenEffectCase lag = generate_hidden_effect_case(Cause::kInputLag, 7);
  EXPECT_GE(lag.effect.lambda, 0.15);
  EXPECT_LE(lag.effect.lambda, 0.5);
  EXPECT_EQ(parse_cause("sensor_drift"), Cause::kSensorDrift);
  EXPECT_EQ(parse_cause("drift"), std::nullopt);
  EXPECT_EQ(none.config.n, none.model.a.size());
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
