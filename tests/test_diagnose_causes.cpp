// lashid diagnose on recordings with a hidden effect, one test per cause (two seeds each). The truth comes from the generator (drawn plant, effect and size), never from the diagnosis itself.
// Seeds 5000+ are used here; the decision thresholds were chosen on seeds 1000-1005 and 2000-2009.
#include <cmath>

#include <gtest/gtest.h>

#include "lashid/analysis/joint_model.hpp"
#include "lashid/diagnose/diagnosis.hpp"
#include "lashid/sim/hidden_effect.hpp"

namespace {

using namespace lashid::sim;

class DiagnoseHiddenEffect : public ::testing::TestWithParam<Cause> {};

TEST_P(DiagnoseHiddenEffect, FindsTheCauseItsParameterAndTheGain) {
  const Cause cause = GetParam();
  for (std::uint64_t seed : {5000U, 5001U}) {
    const HiddenEffectCase c = generate_hidden_effect_case(cause, seed);
    const Diagnosis d = diagnose(c.config, c.recording, "generated");
    SCOPED_TRACE(::testing::Message() << to_string(cause) << " seed " << seed << ": found " << to_string(d.cause)
                                      << " " << to_string(d.parameters));
    ASSERT_EQ(d.cause, cause);
    const HiddenEffect& e = c.effect;
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
    if (cause == Cause::kNone) {
      EXPECT_EQ(d.fit_extended, d.fit_nominal);
      EXPECT_GT(d.fit_nominal, 95.0);
    } else {
      EXPECT_GT(d.fit_extended, d.fit_nominal);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(AllCauses, DiagnoseHiddenEffect, ::testing::ValuesIn(kAllCauses),
                         [](const auto& test_info) { return std::string(to_string(test_info.param)); });

}  // namespace
