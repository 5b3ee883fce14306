// The optional experiment lengths of the config (step_length, pulse_length_d, pulse_length_a, val_length, val_seed):
// their defaults, the rules the reader applies (the firmware's run-time rules), the writer, and the reader's limits.
// Every expected number is worked out by hand from the paper's rules in the comments, not taken from the program.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>

#include "json_text.hpp"
#include "lashid/io/config.hpp"
#include "lashid/io/json.hpp"

#include "data_error_matchers.hpp"

namespace lashid::sim {
namespace config_lengths_test {

using nlohmann::json;
using test::Contains;
using test::error_of;

constexpr std::string_view kSource = "cfg.json";

// The example of docs/data-format.md: n = 2, m = 6, so s = max(n, 2) = 2 and T = s (m + 3) = 18.
json valid_document() {
  return parse_json(R"({"n": 2, "m": 6, "v_min": -3, "v_max": 4,
                         "V_d": [-3, -2, -1, 0, 1, 2], "V_a": [4, 3, 2, 1, 0, -1], "operator": "backlash"})");
}

json with(json document, const std::string& key, json value) {
  document[key] = std::move(value);
  return document;
}

ExperimentConfig parse(const json& document) { return parse_config_json(document.dump(), kSource); }

std::string config_error(const json& document) {
  return error_of([&] { parse(document); });
}

TEST(DefaultPulseLength, IsTheFirstWholeNumberOfPeriodsFromTwoThousand) {
  EXPECT_EQ(default_pulse_length(2, 6), 2016);  // T = 2 * 9 = 18: 2000 / 18 = 111.1, so 112 periods
  EXPECT_EQ(default_pulse_length(3, 8), 2013);  // T = 3 * 11 = 33: 2000 / 33 = 60.6, so 61 periods
  EXPECT_EQ(default_pulse_length(1, 1), 2000);  // s = max(1, 2) = 2, T = 2 * 4 = 8 divides 2000: 250 periods
  EXPECT_EQ(default_pulse_length(1, 8), 2002);  // T = 2 * 11 = 22: 2000 / 22 = 90.9, so 91 periods
  EXPECT_EQ(default_pulse_length(4, 10), 2028);  // the firmware's capacity: T = 4 * 13 = 52, 38.5 -> 39 periods
}

TEST(ConfigLengths, AbsentKeysTakeTheDocumentedDefaults) {
  const ExperimentConfig config = parse(valid_document());
  EXPECT_FALSE(config.step_length);
  EXPECT_FALSE(config.pulse_length_d);
  EXPECT_FALSE(config.pulse_length_a);
  EXPECT_FALSE(config.val_length);
  EXPECT_FALSE(config.val_seed);
  EXPECT_EQ(experiment_lengths(config), (ExperimentLengths{.step_length = 2000,
                                                           .pulse_length_d = 2016,
                                                           .pulse_length_a = 2016,
                                                           .val_length = 1000,
                                                           .val_seed = 1}));
}

TEST(ConfigLengths, GivenKeysAreReadAndOverrideTheDefaultsOneByOne) {
  json document = valid_document();
  document["pulse_length_a"] = 5000;
  const ExperimentConfig only_a = parse(document);
  EXPECT_EQ(experiment_lengths(only_a), (ExperimentLengths{2000, 2016, 5000, 1000, 1}));

  // The least each rule allows: L = n + 1 = 3, N = 2T = 36, no validation; and the largest 32-bit seed.
  document = with(with(with(with(document, "step_length", 3), "pulse_length_d", 36), "val_length", 0), "val_seed",
                  4294967295U);
  const ExperimentConfig config = parse(document);
  EXPECT_EQ(config.step_length, 3);
  EXPECT_EQ(config.pulse_length_d, 36);
  EXPECT_EQ(config.pulse_length_a, 5000);
  EXPECT_EQ(config.val_length, 0);
  EXPECT_EQ(config.val_seed, 4294967295U);
  EXPECT_EQ(experiment_lengths(config), (ExperimentLengths{3, 36, 5000, 0, 4294967295U}));
  EXPECT_EQ(parse(with(valid_document(), "val_seed", 0)).val_seed, 0U);
}

TEST(ConfigLengths, StepLengthMustExceedTheOrder) {
  EXPECT_EQ(config_error(with(valid_document(), "step_length", 2)),
            "cfg.json: 'step_length' = 2 must be greater than n = 2 (the step experiment's mean (3.7) needs L > n)");
  EXPECT_TRUE(Contains(config_error(with(valid_document(), "step_length", -5)), "'step_length' = -5 must be greater"));
  // n = 1: L = 2 is the least.
  const json first_order = with(with(with(valid_document(), "n", 1), "step_length", 2), "V_a", {4, 3, 2, 1, 0, -1});
  EXPECT_EQ(parse(first_order).step_length, 2);
  EXPECT_TRUE(Contains(config_error(with(first_order, "step_length", 1)), "'step_length' = 1 must be greater than n = 1"));
}

TEST(ConfigLengths, PulseLengthsMustCoverTwoPeriods) {
  EXPECT_EQ(config_error(with(valid_document(), "pulse_length_d", 20)),
            "cfg.json: 'pulse_length_d' = 20 is shorter than two pulse periods (2T = 36 for n = 2, m = 6)");
  EXPECT_TRUE(Contains(config_error(with(valid_document(), "pulse_length_a", 35)),
                       "'pulse_length_a' = 35 is shorter than two pulse periods (2T = 36 for n = 2, m = 6)"));
  // n = 3, m = 2: T = 3 * 5 = 15, so 29 is one short.
  const json other = parse_json(R"({"n": 3, "m": 2, "v_min": 0, "v_max": 1, "operator": "switch"})");
  EXPECT_TRUE(Contains(config_error(with(other, "pulse_length_d", 29)), "(2T = 30 for n = 3, m = 2)"));
  EXPECT_EQ(parse(with(other, "pulse_length_d", 30)).pulse_length_d, 30);
}

TEST(ConfigLengths, ValidationLengthAndSeedRanges) {
  EXPECT_EQ(config_error(with(valid_document(), "val_length", -1)), "cfg.json: 'val_length' = -1 must not be negative");
  EXPECT_EQ(config_error(with(valid_document(), "val_seed", -1)),
            "cfg.json: 'val_seed' = -1 must not be negative (an unsigned 32-bit seed)");
  EXPECT_EQ(config_error(with(valid_document(), "val_seed", 4294967296ULL)),
            "cfg.json: 'val_seed' = 4294967296 is too large (at most 4294967295)");
  EXPECT_TRUE(Contains(config_error(with(valid_document(), "val_seed", 18446744073709551615ULL)),
                       "'val_seed' = 18446744073709551615 is too large"));
}

TEST(ConfigLengths, OnlyIntegersWithinAnInt) {
  for (const std::string key : {"step_length", "pulse_length_d", "pulse_length_a", "val_length", "val_seed"}) {
    EXPECT_EQ(config_error(with(valid_document(), key, 2000.0)),
              "cfg.json: '" + key + "' must be an integer, got 2000.0");
    EXPECT_TRUE(Contains(config_error(with(valid_document(), key, "2000")), "must be an integer, got \"2000\""));
    EXPECT_TRUE(Contains(config_error(with(valid_document(), key, nullptr)), "must be an integer, got null"));
  }
  // 2^31 does not fit the int the host counts samples in.
  EXPECT_EQ(config_error(with(valid_document(), "step_length", 2147483648LL)),
            "cfg.json: 'step_length' = 2147483648 is too large (at most 2147483647)");
  EXPECT_EQ(parse(with(valid_document(), "val_length", 2147483647)).val_length, 2147483647);
  // A pulse experiment: at most 2^28 samples, the firmware's rule (its float32 sums lose accuracy beyond).
  EXPECT_EQ(parse(with(valid_document(), "pulse_length_d", 268435456)).pulse_length_d, 268435456);
  EXPECT_EQ(config_error(with(valid_document(), "pulse_length_a", 268435457)),
            "cfg.json: 'pulse_length_a' = 268435457 is too large (at most 268435456)");
}

TEST(ConfigLengths, WriterKeepsExactlyTheGivenKeys) {
  const json without_keys = to_json(parse(valid_document()));
  for (const char* key : {"step_length", "pulse_length_d", "pulse_length_a", "val_length", "val_seed"}) {
    EXPECT_FALSE(without_keys.contains(key)) << key;
  }
  const json document = with(with(valid_document(), "pulse_length_d", 4000), "val_seed", 7);
  const json written = to_json(parse(document));
  EXPECT_EQ(written.at("pulse_length_d"), 4000);
  EXPECT_EQ(written.at("val_seed"), 7);
  EXPECT_FALSE(written.contains("step_length"));
  EXPECT_EQ(parse(written), parse(document));
}

TEST(ConfigLengths, UnknownKeyMessageListsTheNewKeys) {
  EXPECT_TRUE(Contains(config_error(with(valid_document(), "step_lenght", 10)),
                       "unknown key 'step_lenght' (allowed: n, m, v_min, v_max, V_d, V_a, operator, step_length, "
                       "pulse_length_d, pulse_length_a, val_length, val_seed, sensor_range, truth)"));
}

TEST(ConfigSensorRange, OptionalTwoIncreasingNumbersWrittenBackAsGiven) {
  EXPECT_FALSE(parse(valid_document()).sensor_range.has_value());
  const json document = with(valid_document(), "sensor_range", json::array({-50, 75.5}));
  const ExperimentConfig config = parse(document);
  ASSERT_TRUE(config.sensor_range.has_value());
  EXPECT_EQ((*config.sensor_range)[0], -50.0);
  EXPECT_EQ((*config.sensor_range)[1], 75.5);
  EXPECT_EQ(parse(to_json(config)), config);
  EXPECT_EQ(config_error(with(valid_document(), "sensor_range", json::array({5, 5}))),
            "cfg.json: 'sensor_range' = [5, 5] must have lo < hi");
  EXPECT_TRUE(Contains(config_error(with(valid_document(), "sensor_range", json::array({1}))), "'sensor_range'"));
  EXPECT_TRUE(Contains(config_error(with(valid_document(), "sensor_range", "wide")), "'sensor_range'"));
}

TEST(ConfigLimitsTest, ANarrowerRangeIsNamedInItsErrors) {
  const ConfigLimits narrow{.max_order = 2, .max_points = 6, .range_name = "a caller's range"};
  const json third_order = with(valid_document(), "n", 3);
  EXPECT_EQ(parse(third_order).n, 3);  // within the compiled range [1, 4]
  EXPECT_EQ(error_of([&] { parse_config_json(third_order.dump(), kSource, narrow); }),
            "cfg.json: 'n' = 3 is outside a caller's range [1, 2]");
  EXPECT_TRUE(Contains(config_error(with(valid_document(), "n", 5)), "'n' = 5 is outside the compiled range [1, 4]"));
}

}  // namespace config_lengths_test
}  // namespace lashid::sim
