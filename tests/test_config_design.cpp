// A config as the firmware's run-time design (hil's config_design.hpp): the float32 values and lengths the device
// gets, what cannot be expressed, check_design()'s verdict in the config's words, and the samples of a whole run. The
// expected numbers are worked out by hand in the comments from the paper's rules.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "lashid/firmware/run_design.hpp"
#include "lashid/hil/config_design.hpp"
#include "lashid/hil/hil.hpp"
#include "lashid/io/config.hpp"

#include "data_error_matchers.hpp"

namespace lashid::sim {
namespace {

using test::Contains;
using test::error_of;

// The example of docs/data-format.md: n = 2, m = 6, backlash on [-3, 4]; T = max(2, 2) (6 + 3) = 18.
ExperimentConfig example() {
  return parse_config_json(R"({"n": 2, "m": 6, "v_min": -3, "v_max": 4, "V_d": [-3, -2, -1, 0, 1, 2],
                               "V_a": [4, 3, 2, 1, 0, -1], "operator": "backlash"})",
                           "cfg.json");
}

// The design as is, before check_design(): the function `lashid design --check` judges.
fw::RunDesign as_is(const ExperimentConfig& config) {
  return run_design_as_is(config, experiment_lengths(config), "cfg.json");
}

TEST(ConfigDesign, CarriesTheConfigAndItsDefaultLengths) {
  const fw::RunDesign d = to_run_design(example(), "cfg.json");
  EXPECT_EQ(d.op, fw::OperatorKind::kBacklash);
  EXPECT_EQ(d.n, 2);
  EXPECT_EQ(d.m, 6);
  EXPECT_EQ(d.v_min, -3.0f);
  EXPECT_EQ(d.v_max, 4.0f);
  EXPECT_EQ(d.V_d[0], -3.0f);
  EXPECT_EQ(d.V_d[5], 2.0f);
  EXPECT_EQ(d.V_a[0], 4.0f);
  EXPECT_EQ(d.V_a[5], -1.0f);
  EXPECT_EQ(d.step_length, 2000U);
  EXPECT_EQ(d.pulse_length_d, 2016U);  // 112 periods of 18: the first whole number of periods >= 2000
  EXPECT_EQ(d.pulse_length_a, 2016U);
  EXPECT_EQ(d.val_length, 1000U);
  EXPECT_EQ(d.val_seed, 1U);
  EXPECT_EQ(fw::check_design(d), fw::DesignStatus::kOk);
  EXPECT_EQ(design_status_message(fw::DesignStatus::kOk, d), "");
}

TEST(ConfigDesign, CountsTheSamplesOfAWholeRun) {
  ExperimentConfig config = example();
  // Interval check 16T = 288, steps 2 (2000 + 1) = 4002, pulses 2 * 2016 = 4032, validation 1000.
  const FirmwareRunSamples backlash = firmware_run_samples(to_run_design(config, "cfg.json"));
  EXPECT_EQ(backlash.interval_check, 288U);
  EXPECT_EQ(backlash.steps, 4002U);
  EXPECT_EQ(backlash.pulses, 4032U);
  EXPECT_EQ(backlash.validation, 1000U);
  EXPECT_EQ(backlash.total(), 9322U);
  // A switch needs no interval check (Section 3.4 step 1 is about the backlash's loop).
  config.op = OperatorKind::kSwitch;
  config.step_length = 10;
  config.val_length = 0;
  EXPECT_EQ(firmware_run_samples(to_run_design(config, "cfg.json")).total(), 2U * 11U + 4032U);
}

TEST(ConfigDesign, GivenLengthsAndSeedPassThrough) {
  ExperimentConfig config = example();
  config.step_length = 3;
  config.pulse_length_d = 36;
  config.pulse_length_a = 5000;
  config.val_length = 0;
  config.val_seed = 4294967295U;
  const fw::RunDesign d = to_run_design(config, "cfg.json");
  EXPECT_EQ(d.step_length, 3U);
  EXPECT_EQ(d.pulse_length_d, 36U);
  EXPECT_EQ(d.pulse_length_a, 5000U);
  EXPECT_EQ(d.val_length, 0U);
  EXPECT_EQ(d.val_seed, 4294967295U);
  EXPECT_EQ(fw::check_design(d), fw::DesignStatus::kOk);
}

TEST(ConfigDesign, RefusesWhatARunCannotExpress) {
  ExperimentConfig dis_only = example();
  dis_only.V_a.clear();
  EXPECT_TRUE(Contains(error_of([&] { as_is(dis_only); }),
                       "cfg.json: 'V_a' is absent: a firmware run executes both schemes"));
  ExperimentConfig huge = example();
  huge.v_max = 1e300;
  huge.V_a[0] = 1e300;
  EXPECT_TRUE(Contains(error_of([&] { as_is(huge); }),
                       "cfg.json: 'v_max' = 1e+300 is beyond the range of float32"));
  ExperimentConfig wide = example();
  wide.m = 11;
  EXPECT_EQ(error_of([&] { as_is(wide); }),
            "cfg.json: 'm' = 11 is outside the firmware image's capacity [1, 10]");
}

TEST(ConfigDesign, OrdersFitTheImageUpToItsCapacity) {
  ExperimentConfig config = example();
  config.n = 4;  // the image's capacity (and the host estimator's)
  EXPECT_EQ(fw::check_design(to_run_design(config, "cfg.json")), fw::DesignStatus::kOk);
  config.n = 5;
  const fw::RunDesign d = as_is(config);
  EXPECT_EQ(fw::check_design(d), fw::DesignStatus::kOrderOutOfRange);
  EXPECT_EQ(design_status_message(fw::check_design(d), d), "'n' = 5 is outside the firmware image's capacity [1, 4]");
}

// Levels a double tells apart but float32 does not: valid for the host, refused by the image.
TEST(ConfigDesign, LevelsTooCloseInFloat32AreNamedByKey) {
  ExperimentConfig config = parse_config_json(R"({"n": 2, "m": 3, "v_min": 0, "v_max": 1, "operator": "switch",
      "V_d": [0, 0.5, 0.5000000001], "V_a": [1, 0.5, 0.25]})",
                                              "cfg.json");
  fw::RunDesign d = as_is(config);
  EXPECT_EQ(fw::check_design(d), fw::DesignStatus::kVdNotIncreasing);
  EXPECT_EQ(design_status_message(fw::DesignStatus::kVdNotIncreasing, d),
            "in float32 'V_d[2]' = 0.5 is not greater than 'V_d[1]' = 0.5 (V_d strictly increasing, (3.1)): the two "
            "levels are too close for the firmware");

  // 1e-9 above v_min = 0 is a distinct float, but within the classifier's resolution of the held level.
  config.V_d = {0, 0.5, 0.75};
  config.V_a = {1, 0.5, 1e-9};
  d = as_is(config);
  EXPECT_EQ(fw::check_design(d), fw::DesignStatus::kLevelsTooClose);
  EXPECT_TRUE(Contains(design_status_message(fw::DesignStatus::kLevelsTooClose, d),
                       "'V_a': two levels, or a level and the held level v_min, are closer than"));

  // Near float32's range the same test fails because a step overflows: -3e38 - 3e38 = -6e38 > FLT_MAX (3.4e38).
  config.v_min = -3e38;
  config.v_max = 3e38;
  config.V_d = {-3e38, 0, 1e38};
  config.V_a = {3e38, 0, -1e38};
  d = as_is(config);
  EXPECT_EQ(fw::check_design(d), fw::DesignStatus::kLevelsTooClose);
  EXPECT_TRUE(Contains(design_status_message(fw::DesignStatus::kLevelsTooClose, d),
                       "'V_d[0]' = -3e+38 minus the held level 'v_max' = 3e+38 overflows float32"));
}

TEST(ConfigDesign, LengthStatusesNameTheirKeys) {
  fw::RunDesign d = to_run_design(example(), "cfg.json");
  d.pulse_length_d = 20;
  EXPECT_EQ(fw::check_design(d), fw::DesignStatus::kPulseDTooShort);
  EXPECT_EQ(design_status_message(fw::DesignStatus::kPulseDTooShort, d),
            "'pulse_length_d' = 20 is shorter than two pulse periods (2T = 36 for n = 2, m = 6)");
  d.pulse_length_d = 36;
  d.step_length = 2;
  EXPECT_EQ(fw::check_design(d), fw::DesignStatus::kStepTooShort);
  EXPECT_TRUE(Contains(design_status_message(fw::DesignStatus::kStepTooShort, d),
                       "'step_length' = 2 must be greater than n = 2"));
  // 2^32 - 1 validation samples on top of the rest overflow the 32-bit counter.
  d.step_length = 2000;
  d.val_length = 4294967295U;
  EXPECT_EQ(fw::check_design(d), fw::DesignStatus::kRunTooLong);
  EXPECT_TRUE(Contains(design_status_message(fw::DesignStatus::kRunTooLong, d), "shorten 'step_length'"));
  d.val_length = 1000;
  d.pulse_length_a = (1U << 28) + 1;
  EXPECT_EQ(fw::check_design(d), fw::DesignStatus::kPulseTooLong);
  EXPECT_TRUE(Contains(design_status_message(fw::DesignStatus::kPulseTooLong, d),
                       "'pulse_length_a' = 268435457 is longer than the float32 estimator is accurate for"));
}

TEST(ConfigDesign, CheckedConversionsRefuseNamingTheKey) {
  ExperimentConfig config = example();
  config.pulse_length_a = 20;  // not through the reader, which would refuse it first
  EXPECT_EQ(error_of([&] { to_run_design(config, "cfg.json"); }),
            "cfg.json: the firmware image cannot run this design: 'pulse_length_a' = 20 is shorter than two pulse "
            "periods (2T = 36 for n = 2, m = 6) (firmware status: pulse_length_a shorter than two pulse periods "
            "(Theorem 3.1))");
  // hil's form with explicit lengths (a scenario's) goes through the same conversion and words.
  const RunLengths lengths{.step_length = 2000, .pulse_length_d = 36, .pulse_length_a = 35, .val_length = 0,
                           .val_seed = 1};
  try {
    (void)to_run_design(example(), lengths);
    ADD_FAILURE() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_TRUE(Contains(e.what(), "the firmware cannot run this design: 'pulse_length_a' = 35 is shorter"));
  }
  ExperimentConfig dis_only = example();
  dis_only.V_a.clear();
  EXPECT_THROW((void)to_run_design(dis_only, lengths), std::invalid_argument);
}

}  // namespace
}  // namespace lashid::sim
