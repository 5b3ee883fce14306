// lashid diagnose on recordings with hidden effects: one test per cause (two seeds each) on borders linear between
// the levels, the causes the docs report at 100 % on curved borders, and a pair. The truth comes from the
// generator (drawn plant, effects and sizes), never from the diagnosis itself. Seeds 5000+ are used here; the
// decision thresholds were chosen on seeds 1000-1009 (and 1000-1005, 2000-2009 before issue 12).
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "lashid/analysis/joint_model.hpp"
#include "lashid/diagnose/diagnosis.hpp"
#include "lashid/sim/hidden_effect.hpp"

namespace {

using namespace lashid::sim;

// Every hidden cause found, none other, each size within the tolerance; the strongest cause first.
void expect_found(const HiddenEffectCase& c, const Diagnosis& d) {
  const HiddenEffect& e = c.effect;
  std::vector<Cause> hidden = e.causes, found = d.causes;
  std::sort(hidden.begin(), hidden.end());
  std::sort(found.begin(), found.end());
  ASSERT_EQ(found, hidden);
  ASSERT_EQ(d.cause, d.causes.front());
  for (Cause cause : e.causes) {
    switch (cause) {
      case Cause::kInputLag:
        ASSERT_TRUE(d.parameters.lambda);
        EXPECT_NEAR(*d.parameters.lambda, e.lambda, 0.05);
        break;
      case Cause::kDeadTime:
        EXPECT_EQ(d.parameters.delay, e.delay);
        break;
      case Cause::kSensorDrift:
        ASSERT_TRUE(d.parameters.drift_total);
        EXPECT_NEAR(*d.parameters.drift_total, e.drift_total, 0.2 * std::abs(e.drift_total));
        break;
      case Cause::kOperatorType:
        EXPECT_EQ(d.parameters.op, e.true_operator);
        break;
      default:
        break;
    }
  }
  if (e.cause == Cause::kNone) {
    EXPECT_EQ(d.fit_extended, d.fit_nominal);
    EXPECT_TRUE(d.added.empty());
  } else {
    EXPECT_GT(d.fit_extended, d.fit_nominal);
    EXPECT_EQ(d.added.size(), e.causes.size());
  }
}

class DiagnoseHiddenEffect : public ::testing::TestWithParam<Cause> {};

TEST_P(DiagnoseHiddenEffect, FindsTheCauseItsParameterAndTheGain) {
  const Cause cause = GetParam();
  for (std::uint64_t seed : {5000U, 5001U}) {
    const HiddenEffectCase c = generate_hidden_effect_case(cause, seed);
    const Diagnosis d = diagnose(c.config, c.recording, "generated");
    SCOPED_TRACE(::testing::Message() << to_string(cause) << " seed " << seed << ": found " << to_string(d.cause)
                                      << " " << to_string(d.parameters));
    expect_found(c, d);
    if (cause == Cause::kNone) {
      EXPECT_GT(d.fit_nominal, 95.0);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(AllCauses, DiagnoseHiddenEffect, ::testing::ValuesIn(kAllCauses),
                         [](const auto& test_info) { return std::string(to_string(test_info.param)); });

// Borders curved between the levels (tanh and sine terms): the causes docs/diagnose.md reports at 100 % on the
// tuning seeds. input_lag and colored_noise are below that there, so a single seed would test luck, not the rate.
TEST(DiagnoseCurvedBorders, FindsTheCausesTheDocsReportAtFullRate) {
  HiddenEffectOptions curved;
  curved.borders = BorderShape::kCurved;
  for (Cause cause : {Cause::kNone, Cause::kDeadTime, Cause::kSensorDrift, Cause::kOperatorType}) {
    const std::array<Cause, 1> hidden{cause};
    const HiddenEffectCase c = generate_hidden_effect_case(hidden, 5000, curved);
    const Diagnosis d = diagnose(c.config, c.recording, "generated");
    SCOPED_TRACE(::testing::Message() << to_string(cause) << ": found " << to_string(d.cause) << " "
                                      << to_string(d.parameters));
    expect_found(c, d);
  }
}

// The pair docs/diagnose.md reports at full rate (20 of 20 test seeds). The others are below 90 % there; one of
// their misses is sensor_drift + colored_noise on this very seed (a dead time and an input lag are added to absorb
// the coloured noise, each raising the val fit), listed under "What still fails".
TEST(DiagnosePairs, NamesBothHiddenCausesOnCurvedBorders) {
  HiddenEffectOptions curved;
  curved.borders = BorderShape::kCurved;
  const std::array<std::array<Cause, 2>, 1> pairs{{{Cause::kDeadTime, Cause::kOperatorType}}};
  for (const auto& pair : pairs) {
    const HiddenEffectCase c = generate_hidden_effect_case(pair, 5000, curved);
    const Diagnosis d = diagnose(c.config, c.recording, "generated");
    SCOPED_TRACE(::testing::Message() << to_string(pair[0]) << "+" << to_string(pair[1]) << ": found "
                                      << d.causes.size() << " causes " << to_string(d.parameters));
    expect_found(c, d);
  }
}

}  // namespace
